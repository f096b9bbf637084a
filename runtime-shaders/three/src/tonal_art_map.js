// BAKER_tonal_art_map: hatching with the baked tonal art map (packed layout).
import * as THREE from 'three';
import { descriptorUniforms, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/**
 * The TAM's packed textures as two textures whose mip chains are the TAM's own levels (Praun et al. 2001): level i
 * of the extension is uploaded as mip level i, as baker_hatching.glsl expects.
 */
export async function tamTextures(parser, ext) {
	const levels = ext.levels || [];
	const loaded = await Promise.all(levels.map((l) => Promise.all((l.textures || []).map((t) => textureOf(parser, t)))));
	return [0, 1].map((k) => {
		const images = loaded.map((pair) => pair[k].image);
		const texture = new THREE.Texture(images[0]);
		texture.mipmaps = images;
		texture.colorSpace = THREE.NoColorSpace;
		texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
		texture.magFilter = THREE.LinearFilter;
		texture.minFilter = THREE.LinearMipmapLinearFilter;
		texture.generateMipmaps = false;
		texture.flipY = false;
		texture.needsUpdate = true;
		return texture;
	});
}

/** The three.js attribute GLTFLoader gives TEXCOORD_<n> (n > 0), or null for TEXCOORD_0 (the surface's `uv`). */
export function tamUvAttribute(texCoord) {
	if (!texCoord) return null;
	return texCoord <= 3 ? `uv${texCoord}` : `texcoord_${texCoord}`;
}

/** GLTFLoader plugin for BAKER_tonal_art_map (packed layout): hatching strokes, tone from the key light. */
export const BakerTonalArtMapPlugin = surfacePlugin('tam', async function (ext) {
	if ((ext.layout ?? 'packed') !== 'packed' || !ext.levels?.length) {
		console.warn('@baker/three: BAKER_tonal_art_map: only the packed layout is drawn by this plugin');
		return null;
	}
	const [t012, t345] = await tamTextures(this.parser, ext);
	const { uniforms, types } = descriptorUniforms('tonal_art_map', ext);
	// the UV set it tiles over: TEXCOORD_0 is the surface's own `uv`; another (baker's stroke parameterization) is the
	// attribute GLTFLoader names uv1..uv3 (texcoord_<n> beyond), carried to the stage as BAKER_TAM_UV
	const set = tamUvAttribute(ext.texCoord ?? 0);
	return {
		glsl: (set ? `#define BAKER_TAM_UV vBaker${set}\n` : '') + requireShader(this.shaders, 'hatching'),
		attributes: set ? [[set, 'vec2']] : [],
		uvAttribute: set, // the node material (./node/surface.js) reads the set directly
		uniforms: { ...uniforms, u_bakerTam012: { value: t012 }, u_bakerTam345: { value: t345 } },
		types: { ...types, u_bakerTam012: 'sampler2D', u_bakerTam345: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerTonalArtMapPlugin];
