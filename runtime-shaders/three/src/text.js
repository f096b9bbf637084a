// BAKER_text: a label's glyph quads drawn with the distance-field shader (outline, glow, shadow).
import * as THREE from 'three';
import { textFieldType, textShadowOffset, textStyle } from '@baker/shared';
import { BAKER_TEXT, controls, requireShader } from './common.js';
import { BakerGlyphAtlasPlugin } from './glyph_atlas.js';

const TEXT_VERTEX = `
varying vec2 vUvText;
void main() {
	vUvText = uv;
	gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const TEXT_FRAGMENT = `
uniform sampler2D u_atlas;
uniform BakerTextStyle u_style;
uniform int u_fieldType;
uniform float u_distanceRange;
uniform vec2 u_shadowOffset;
varying vec2 vUvText;
void main() {
	vec2 atlasSize = vec2(textureSize(u_atlas, 0));
	float range = baker_text_screen_px_range(u_distanceRange, atlasSize, fwidth(vUvText));
	vec4 texel = texture(u_atlas, vUvText);
	vec4 shadowTexel = texture(u_atlas, vUvText - u_shadowOffset);
	vec4 color = baker_text_shade(u_style, texel, shadowTexel, u_fieldType, u_distanceRange, range);
	if (color.a <= 0.0) discard;
	gl_FragColor = color;  // premultiplied
}`;

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
			// the BakerTextStyle struct: the shared style with its [r, g, b, a] colours as vec4 values
			const style = textStyle(ext, font, '@baker/three');
			for (const key of ['color', 'outlineColor', 'glowColor', 'shadowColor']) style[key] = new THREE.Vector4(...style[key]);
			const offset = textShadowOffset(ext, font);
			const uniforms = {
				u_atlas: { value: texture }, u_style: { value: style }, u_fieldType: { value: textFieldType(font) },
				u_distanceRange: { value: font.distanceRange ?? 4 },
				u_shadowOffset: { value: new THREE.Vector2(...offset) },
			};
			const material = new THREE.ShaderMaterial({
				name: 'baker MSDF text', uniforms, vertexShader: TEXT_VERTEX,
				fragmentShader: requireShader(this.shaders, 'text') + TEXT_FRAGMENT,
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
