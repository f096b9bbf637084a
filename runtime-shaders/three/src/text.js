// BAKER_text: a label's glyph quads drawn with the distance-field shader (outline, glow, shadow); the stages are
// runtime-shaders/hosts/web/text.*.glsl.
import * as THREE from 'three';
import { textFieldType, textShadowOffset, textStyle } from '@baker/shared';
import { BAKER_TEXT, controls, requireShader, stageMaterial } from './common.js';
import { BakerGlyphAtlasPlugin } from './glyph_atlas.js';

/** GLTFLoader plugin for BAKER_text: the label's glyph quads drawn with the distance-field shader (outline, glow, shadow).
 * The quads are baker's shaped run (BAKER_text.glyphs: ligatures, bidi, fallback fonts), and glyphs from every font of
 * the fallback list share the one atlas texture of BAKER_glyph_atlas.fonts[font], so a mixed-script label is one
 * material and one draw. */
export class BakerTextPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_TEXT;
		this.shaders = options.shaders || {};
		this.atlas = new BakerGlyphAtlasPlugin(parser);
	}

	async afterRoot(result) {
		const c = controls(this.parser);
		const nodes = this.parser.json.nodes || [];
		const labels = [];
		result.scene.traverse((o) => {
			const index = this.parser.associations.get(o)?.nodes;
			const ext = index !== undefined && nodes[index]?.extensions?.[BAKER_TEXT];
			if (ext) labels.push([o, ext]);
		});
		for (const [node, ext] of labels) {
			const atlas = await this.atlas.font(ext.font ?? 0);
			if (!atlas) continue;
			const { font, texture } = atlas;
			// the style's fields as uniforms u_<field>, its [r, g, b, a] colours as vec4 values
			const style = textStyle(ext, font, '@baker/three');
			const offset = textShadowOffset(ext, font);
			const uniforms = {
				...Object.fromEntries(Object.entries(style).map(([key, v]) => [`u_${key}`, { value: Array.isArray(v) ? new THREE.Vector4(...v) : v }])),
				u_atlas: { value: texture }, u_fieldType: { value: textFieldType(font) },
				u_distanceRange: { value: font.distanceRange ?? 4 },
				u_shadowOffset: { value: new THREE.Vector2(...offset) },
			};
			const material = stageMaterial({
				name: 'baker MSDF text', uniforms, glsl: requireShader(this.shaders, 'text'), vertex: 'text.vert', fragment: 'text.frag',
				transparent: true, depthWrite: false, side: THREE.DoubleSide,
				blending: THREE.CustomBlending, blendSrc: THREE.OneFactor, blendDst: THREE.OneMinusSrcAlphaFactor,
			});
			node.traverse((o) => {
				if (!o.isMesh) return;
				const fallback = o.material; // glTF's alpha-tested single-channel field
				c.add('text', (on) => { o.material = on ? material : fallback; });
			});
		}
		return null;
	}
}

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerTextPlugin];
