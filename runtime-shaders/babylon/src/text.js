// BAKER_text: a label's glyph quads drawn with the distance-field shader (outline, glow, shadow; RTR4 15.5).
import { textFieldType, textShadowOffset, textStyle as sharedTextStyle } from '@baker/shared';
import { BAKER_TEXT, bakerShaderMaterial, controls, requireShader } from './common.js';
import { premultiplied } from './geometry.js';
import { glyphAtlasFont } from './glyph_atlas.js';

const TEXT_VERTEX = `
attribute vec3 position;
attribute vec2 uv;
uniform mat4 worldViewProjection;
varying vec2 vUvText;
void main() {
	vUvText = uv;
	gl_Position = worldViewProjection * vec4(position, 1.0);
}`;

const STYLE_FIELDS = ['color', 'softness', 'outlineColor', 'outlineWidth', 'glowColor', 'glowWidth', 'shadowColor', 'shadowSoftness'];

const TEXT_FRAGMENT = `
uniform sampler2D u_atlas;
uniform vec4 u_color;
uniform float u_softness;
uniform vec4 u_outlineColor;
uniform float u_outlineWidth;
uniform vec4 u_glowColor;
uniform float u_glowWidth;
uniform vec4 u_shadowColor;
uniform float u_shadowSoftness;
uniform int u_fieldType;
uniform float u_distanceRange;
uniform vec2 u_shadowOffset;
varying vec2 vUvText;
void main() {
	BakerTextStyle style = BakerTextStyle(u_color, u_softness, u_outlineColor, u_outlineWidth, u_glowColor, u_glowWidth,
		u_shadowColor, u_shadowSoftness);
	vec2 atlasSize = vec2(textureSize(u_atlas, 0));
	float range = baker_text_screen_px_range(u_distanceRange, atlasSize, fwidth(vUvText));
	vec4 texel = texture(u_atlas, vUvText);
	vec4 shadowTexel = texture(u_atlas, vUvText - u_shadowOffset);
	vec4 color = baker_text_shade(style, texel, shadowTexel, u_fieldType, u_distanceRange, range);
	if (color.a <= 0.0) discard;
	gl_FragColor = color;  // premultiplied
}`;

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
			const material = premultiplied(bakerShaderMaterial('baker MSDF text', scene, {
				vertex: TEXT_VERTEX, fragment: requireShader(this.shaders, 'text') + TEXT_FRAGMENT,
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
