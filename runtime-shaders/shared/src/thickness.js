// BAKER_thickness: the translucency parameters both runtimes read (GDC 2011 form of RTR4 eq. 14.30).

/** Translucency parameters of a material's BAKER_thickness, with the extension's defaults filled in. */
export function thicknessParameters(ext) {
	return {
		attenuationDistance: ext.attenuationDistance ?? ext.meanThickness ?? 1,
		distortion: ext.distortion ?? 0.2,
		power: ext.power ?? 4,
		scale: ext.scale ?? 1,
		ambient: ext.ambient ?? 0,
		subsurfaceColor: (ext.subsurfaceColor ?? [1, 1, 1]).slice(0, 3),
		attribute: ext.attribute ?? null,
	};
}
