// BAKER_text: the label style and shadow offset both runtimes give the distance-field shader (baker_text.glsl).

const FIELD_TYPES = { sdf: 0, psdf: 1, msdf: 2, mtsdf: 3 };

/** The shader's u_fieldType of an atlas font's field type (MSDF when the font does not say). */
export function textFieldType(font) {
	return FIELD_TYPES[font.type] ?? 2;
}

/**
 * BAKER_text style in atlas pixels (em x font size), the extension's defaults filled in (colours as [r, g, b, a]),
 * the outline capped by the range; `packageName` names the runtime in the warning when it is capped.
 */
export function textStyle(ext, font, packageName) {
	const size = font.size ?? 32;
	const rgba = (a, d) => (a ?? d).concat([1, 1, 1, 1]).slice(0, 4);
	const style = {
		color: rgba(ext.color, [1, 1, 1, 1]), softness: ext.softness ?? 0,
		outlineColor: rgba(ext.outline?.color, [0, 0, 0, 1]), outlineWidth: (ext.outline?.width ?? 0) * size,
		glowColor: rgba(ext.glow?.color, [1, 1, 1, 0]), glowWidth: (ext.glow?.width ?? 0) * size,
		shadowColor: rgba(ext.shadow?.color, [0, 0, 0, 0]), shadowSoftness: (ext.shadow?.softness ?? 0) * size,
	};
	if (!ext.shadow) style.shadowColor[3] = 0;
	// the field saturates half a range outside the glyph: a wider outline would fill the whole quad
	const widest = 0.5 * (font.distanceRange ?? 4) - 0.5;
	if (style.outlineWidth > widest) {
		console.warn(`${packageName}: BAKER_text outline (${style.outlineWidth.toFixed(2)} atlas px) is wider than the ` +
			`atlas distance range allows; drawn ${widest} px wide`);
		style.outlineWidth = widest;
	}
	return style;
}

/** The shadow offset of BAKER_text in atlas UV (the extension gives it in em). */
export function textShadowOffset(ext, font) {
	const size = font.size ?? 32;
	const offset = ext.shadow?.offset ?? [0, 0];
	return [offset[0] * size / (font.width ?? 1), offset[1] * size / (font.height ?? 1)];
}
