// BAKER_tonal_art_map: hatching with the baked tonal art map, packed layout (Praun et al. 2001; RTR4 15.3).
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { BaseTexture } from '@babylonjs/core/Materials/Textures/baseTexture.js';
import { RawTexture } from '@babylonjs/core/Materials/Textures/rawTexture.js';
import { BAKER_TONAL_ART_MAP, descriptorUniforms, loadedPrimitives, partModule, setAttribute, uploadMipLevels } from './common.js';
import { surfaceExtension } from './surface.js';

async function decodeImage(loader, textureIndex) {
	const texture = loader.gltf.textures[textureIndex];
	const image = loader.gltf.images[texture.source];
	const bytes = await loader.loadImageAsync(`/images/${texture.source}`, image);
	const blob = new Blob([bytes], { type: image.mimeType || 'image/png' });
	return createImageBitmap(blob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
}

/**
 * The TAM's packed textures as two textures whose mip chains are the TAM's own levels: level i of the extension is
 * uploaded as mip level i (TEXTURE_MAX_LEVEL = levels - 1), as baker_hatching.glsl expects, repeating, trilinear.
 */
export async function tamTextures(loader, ext) {
	const levels = ext.levels || [];
	const images = await Promise.all(levels.map((l) => Promise.all((l.textures || []).map((t) => decodeImage(loader, t.index ?? t)))));
	const engine = loader.babylonScene.getEngine();
	if (engine.isWebGPU) return tamRawTextures(loader.babylonScene, images, levels[0].size);
	const gl = engine._gl;
	return [0, 1].map((k) => {
		const handle = gl.createTexture();
		gl.bindTexture(gl.TEXTURE_2D, handle);
		engine._unpackFlipY(false);
		gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
		gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
		images.forEach((pair, level) => gl.texImage2D(gl.TEXTURE_2D, level, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, pair[k]));
		gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_BASE_LEVEL, 0);
		gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAX_LEVEL, images.length - 1);
		gl.bindTexture(gl.TEXTURE_2D, null);
		engine.resetTextureCache();
		const size = levels[0].size;
		const internal = engine.wrapWebGLTexture(handle, true, Constants.TEXTURE_TRILINEAR_SAMPLINGMODE, size, size);
		const texture = new BaseTexture(loader.babylonScene, internal);
		texture.name = `baker TAM tones ${k ? '3-5' : '0-2'}`;
		texture.gammaSpace = false;
		texture.wrapU = texture.wrapV = Constants.TEXTURE_WRAP_ADDRESSMODE;
		return texture;
	});
}

// The RGBA8 texels of a decoded image, as stored (no premultiplication, no colour conversion: the PNGs are data)
function imageTexels(image) {
	const canvas = new OffscreenCanvas(image.width, image.height);
	const context = canvas.getContext('2d', { colorSpace: 'srgb', willReadFrequently: true });
	context.drawImage(image, 0, 0);
	return new Uint8Array(context.getImageData(0, 0, image.width, image.height).data.buffer);
}

/**
 * tamTextures on WebGPUEngine (no GL context to upload level by level): a RawTexture per pair created with its mip
 * storage, then every TAM level uploaded over mip level i (uploadMipLevels), as coverageMipsTexture does.
 */
function tamRawTextures(scene, images, size) {
	return [0, 1].map((k) => {
		const levels = images.map((pair) => ({ data: imageTexels(pair[k]), width: pair[k].width, height: pair[k].height }));
		const texture = new RawTexture(levels[0].data, size, size, Constants.TEXTUREFORMAT_RGBA, scene, true, false,
			Constants.TEXTURE_TRILINEAR_SAMPLINGMODE, Constants.TEXTURETYPE_UNSIGNED_BYTE);
		uploadMipLevels(texture, levels);
		texture.name = `baker TAM tones ${k ? '3-5' : '0-2'}`;
		texture.gammaSpace = false;
		texture.wrapU = texture.wrapV = Constants.TEXTURE_WRAP_ADDRESSMODE;
		return texture;
	});
}

/** Loader extension for BAKER_tonal_art_map (packed layout): hatching strokes, tone from the key light. */
export const BakerTonalArtMapExtension = surfaceExtension('tam', BAKER_TONAL_ART_MAP, async function (ext, mesh, primitive, material) {
	if ((ext.layout ?? 'packed') !== 'packed' || !ext.levels?.length) {
		console.warn('@baker/babylon: BAKER_tonal_art_map: only the packed layout is drawn by this extension');
		return null;
	}
	// the UV set it tiles over: TEXCOORD_0 is the surface's own `uv`; another (baker's stroke parameterization) goes
	// on every mesh drawn with the material as vertex data `bakerTamUv`, carried to the stage as BAKER_TAM_UV
	const texCoord = ext.texCoord ?? 0;
	if (texCoord) {
		const name = `TEXCOORD_${texCoord}`;
		for (const other of loadedPrimitives(this.loader)) {
			if (other.primitive.material === primitive.material && other.mesh.material === mesh.material &&
				!(await setAttribute(this.loader, other.mesh, other.primitive, name, 'bakerTamUv'))) return null;
		}
	}
	const [t012, t345] = await tamTextures(this.loader, ext);
	const module = partModule(this, 'hatching', material);
	return {
		...(module.glsl ? { glsl: (texCoord ? '#define BAKER_TAM_UV v_bakerTamUv\n' : '') + module.glsl } : module),
		attributes: texCoord ? [['bakerTamUv', 2]] : [],
		// the varying the WGSL stage reads as bakerTamUv (WGSL has no preprocessor for the GLSL stage's define)
		tamUv: texCoord ? 'v_bakerTamUv' : null,
		samplers: { u_bakerTam012: t012, u_bakerTam345: t345 },
		...descriptorUniforms('tonal_art_map', ext),
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_TONAL_ART_MAP]: BakerTonalArtMapExtension };
