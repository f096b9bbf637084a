// BAKER_text: a label's glyph quads drawn with the distance-field shader (outline, glow, shadow; RTR4 15.5); the
// stages are runtime-shaders/hosts/web/text.*.glsl.
import { textFieldType, textShadowOffset, textStyle as sharedTextStyle } from '@baker/shared';
import { BAKER_GLYPH_ATLAS, BAKER_TEXT, controls, engineModule, stageMaterial } from './common.js';
import { premultiplied } from './geometry.js';
import { BakerGlyphAtlasExtension, glyphAtlasFont } from './glyph_atlas.js';

const STYLE_FIELDS = ['color', 'softness', 'outlineColor', 'outlineWidth', 'glowColor', 'glowWidth', 'shadowColor', 'shadowSoftness'];

/** BAKER_text style in atlas pixels (em x font size), the extension's defaults filled in, the outline capped by the range. */
export function textStyle(ext, font) {
	return sharedTextStyle(ext, font, '@baker/babylon');
}

/** Loader extension for BAKER_text: each label node's quads get the distance-field material; off: glTF's alpha-tested fallback. */
export class BakerTextExtension {
	constructor(loader, options = {}) {
		this.name = BAKER_TEXT;
		this.enabled = true;
		this.order = 240;
		this.loader = loader;
		this.shaders = options.shaders || {};
		this.options = options;
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		for (const node of loader.gltf.nodes || []) {
			const ext = node.extensions?.[BAKER_TEXT];
			if (!ext || !node._primitiveBabylonMeshes) continue;
			const atlas = await glyphAtlasFont(loader, ext.font ?? 0);
			if (!atlas) continue;
			const { font, texture } = atlas;
			const style = textStyle(ext, font);
			const offset = textShadowOffset(ext, font);
			const material = premultiplied(stageMaterial('baker MSDF text', scene, {
				glsl: engineModule(this, 'text', scene), vertex: 'text.vert', fragment: 'text.frag',
				attributes: ['position', 'uv'], samplers: ['u_atlas'], alpha: true,
				uniforms: [...STYLE_FIELDS.map((f) => `u_${f}`), 'u_fieldType', 'u_distanceRange', 'u_shadowOffset'],
			}));
			material.setTexture('u_atlas', texture);
			for (const f of STYLE_FIELDS) {
				const v = style[f];
				if (Array.isArray(v)) material.setVector4(`u_${f}`, { x: v[0], y: v[1], z: v[2], w: v[3] });
				else material.setFloat(`u_${f}`, v);
			}
			material.setInt('u_fieldType', textFieldType(font));
			material.setFloat('u_distanceRange', font.distanceRange ?? 4);
			material.setVector2('u_shadowOffset', { x: offset[0], y: offset[1] });
			material.backFaceCulling = false;
			for (const mesh of node._primitiveBabylonMeshes) {
				const fallback = mesh.material; // glTF's alpha-tested single-channel field
				c.add('text', (on) => { mesh.material = on ? material : fallback; });
			}
		}
	}
}

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_TEXT]: BakerTextExtension, [BAKER_GLYPH_ATLAS]: BakerGlyphAtlasExtension };
