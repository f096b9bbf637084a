// The surface techniques on WebGPURenderer: the material GLTFLoader made becomes a node material of the same kind
// (MeshStandardNodeMaterial / MeshPhysicalNodeMaterial, every property copied, as the renderer's own conversion
// does), whose lighting model is three.js's PhysicalLightingModel with baker's terms added per directional light
// and whose output takes the outgoing-colour techniques. The parts (textures, uniforms, attributes) are the ones the
// WebGL plugins gathered (../surface.js BakerSurface), read here, so both renderers draw one asset from one set of
// parts and one switch registry; the formulas are the runtime-shaders/ modules' (./modules.js). What the WebGL path
// does in GLSL (../surface.js inject) is done here in the same order:
//   per directional light: f = N.L -> blurred normals' per-channel N.L -> skin LUT -> toon ramp; the change to
//   Lambert's term on the base colour; translucency added; hair cards' Kajiya-Kay instead of Lambert; after the
//   lights the caustics scale the sun's Lambert light; on the outgoing colour hatching, then the curvature view.
import { MeshPhysicalNodeMaterial, MeshStandardNodeMaterial, Vector3 } from 'three/webgpu';
import {
	BRDF_Lambert, attribute, clamp, dFdx, dFdy, diffuseColor, diffuseContribution, dot, float, fwidth, mix, modelViewMatrix, normalView,
	normalViewGeometry, normalize, positionView, positionViewDirection, positionWorld, reference, saturate, select,
	texture, uniform, uv, varying, vec2, vec3, vec4, Fn, mat3, tangentView, bitangentView,
} from 'three/tsl';

const TYPES = { float: 'float', int: 'int', vec2: 'vec2', vec3: 'vec3', vec4: 'vec4' };

/** A TSL node reading the value of one BakerSurface uniform (kept in step with the switches and the caustics clock). */
function ref(surface, name, type = 'float') {
	const holder = surface.uniforms[name];
	if (!holder) throw new Error(`@baker/three: surface uniform ${name} missing`);
	return reference('value', TYPES[type] ?? type, holder);
}

const on = (surface, name) => ref(surface, `u_baker_${name}_on`).greaterThan(0.5);

/** The view-space direction towards the first directional light of the scene (WebGL's directionalLights[0]). */
function keyLight() {
	const direction = new Vector3(0, 0, 1);
	const a = new Vector3();
	const b = new Vector3();
	return uniform(direction).onRenderUpdate(({ scene, camera }) => {
		let light = null;
		scene?.traverseVisible((o) => { if (!light && o.isDirectionalLight) light = o; });
		if (!light || !camera) return direction.set(0, 0, 1);
		a.setFromMatrixPosition(light.matrixWorld);
		b.setFromMatrixPosition(light.target.matrixWorld);
		return direction.subVectors(a, b).transformDirection(camera.matrixWorldInverse);
	});
}

/**
 * The per-material TSL of baker's surface techniques from a BakerSurface (its parts and uniforms), for the
 * modules `m` (BakerModules). Returns { direct(lightData), afterLights(builder), output(color) }.
 */
export function surfaceNodes(surface, m) {
	const p = surface.parts;
	const u = (name, type) => {
		const spec = Object.values(p).find((part) => part.types?.[name]);
		return ref(surface, name, type ?? spec?.types[name] ?? 'float');
	};
	const tex = (name) => surface.uniforms[name].value;

	// ---- per light: the change of Lambert's N.L term (WebGL: ../surface.js `diffuse`)
	const vertexUv = uv();
	let normalBlur = null;
	if (p.normalBlur) {
		// the three maps at the normal map's UV through the normal map's tangent frame, as the WebGL path's `tbn`:
		// the vertex TANGENT where the geometry has one, else the module's derivative frame
		// (baker_normal_blur_derivative_frame, three's getTangentFrame)
		const flip = u('u_bakerNormalBlurFlipY', 'float');
		const decode = m.fn('normalBlur', 'baker_normal_blur_decode');
		const map = surface.material.normalMap;
		const mapUv = uv(map?.channel ?? 0);
		const derivative = m.fn('normalBlur', 'baker_normal_blur_derivative_frame')(normalViewGeometry, dFdx(positionView),
			dFdy(positionView), dFdx(mapUv), dFdy(mapUv));
		const frame = Fn((builder) => (builder.geometry?.hasAttribute('tangent')
			? mat3(tangentView, bitangentView, normalViewGeometry) : derivative))();
		const decoded = (name) => normalize(frame.mul(decode(texture(tex(name), mapUv).rgb, flip)));
		normalBlur = {
			red: decoded('u_bakerNormalBlurRed'), green: decoded('u_bakerNormalBlurGreen'), blue: decoded('u_bakerNormalBlurBlue'),
			ndotl: m.fn('normalBlur', 'baker_normal_blur_ndotl'),
		};
	}

	let skinCurvature = null;
	if (p.skin) {
		const names = (p.skin.attributes || []).map(([n]) => n);
		const principal = names.find((n) => n === '_principal_curvatures');
		const direction = names.find((n) => n === '_principal_direction');
		const mean = names.find((n) => n !== principal && n !== direction);
		if (principal && direction) {
			const d = attribute(direction, 'vec3');
			const dView = modelViewMatrix.mul(vec4(d, 0)).xyz;
			// into view space in the vertex stage, its length kept (as the WebGL part's vertex expression)
			const dKept = varying(dView.mul(d.length().div(dView.length().max(1e-20))));
			const k = attribute(principal, 'vec2');
			const along = m.fn('skin', 'baker_skin_curvature_along_light');
			skinCurvature = (L) => along(k, dKept, normalViewGeometry, L);
		} else if (mean) {
			const k = attribute(mean, 'float');
			skinCurvature = () => k;
		} else {
			const fromDerivatives = m.fn('skin', 'baker_skin_curvature_from_derivatives');
			skinCurvature = () => fromDerivatives(fwidth(normalViewGeometry), fwidth(positionView));
		}
	}

	function skinLut(ndotl3, k) {
		const lut = tex('u_bakerSkinLut');
		const size = vec2(lut.image?.width ?? 1, lut.image?.height ?? 1);
		const curvature = m.fn('skin', 'baker_skin_curvature')(k, u('u_bakerSkinCurvatureScale'));
		const lutUv = m.fn('skin', 'baker_skin_lut_uv');
		const range = u('u_bakerSkinCurvatureRange');
		const read = (c) => texture(lut, lutUv(c, curvature, range, size));
		return vec3(read(ndotl3.x).r, read(ndotl3.y).g, read(ndotl3.z).b);
	}

	let cards = null;
	if (p.cards) {
		const cardsUv = vertexUv;
		const data = texture(tex('u_bakerCardsData'), cardsUv).rgb;
		const frame = m.fn('cards', 'baker_hair_cards_frame')(normalView, dFdx(positionView), dFdy(positionView),
			dFdx(cardsUv), dFdy(cardsUv));
		const T = m.fn('cards', 'baker_hair_cards_flow')(texture(tex('u_bakerCardsFlow'), cardsUv).rgb, normalView, frame);
		cards = { data, T, shade: m.fn('cards', 'baker_hair_cards_shade') };
	}

	const sun = [];  // the directional lights' Lambert light on the base colour, for the caustics

	function direct({ lightDirection: L, lightColor, reflectedLight, lightNode }) {
		if (lightNode?.light && !lightNode.light.isDirectionalLight) return;  // WebGL: NUM_DIR_LIGHTS only
		const N = normalView;
		const dotNL = dot(N, L);
		const lambert = vec3(saturate(dotNL));
		let f = lambert;
		let ndotl3 = null;
		if (normalBlur) {
			ndotl3 = normalBlur.ndotl(normalBlur.red, normalBlur.green, normalBlur.blue, L);
			f = select(on(surface, 'normalBlur'), clamp(ndotl3, 0, 1), f);
		}
		if (p.skin) {
			const k = skinCurvature(L);
			const blended = m.fn('skin', 'baker_skin_blended_ndotl')(N, N, L, u('u_bakerSkinNormalBlend'));
			const skin = ndotl3 ? select(on(surface, 'normalBlur'), skinLut(ndotl3, k), skinLut(blended, k)) : skinLut(blended, k);
			f = select(on(surface, 'skin'), skin, f);
		}
		if (p.toon) {
			const nl = p.skin ? select(on(surface, 'skin'), dot(f, vec3(0.2126, 0.7152, 0.0722)).mul(2).sub(1), dotNL) : dotNL;
			const ramp = tex('u_bakerToonRamp');
			const toonU = m.fn('toon', 'baker_toon_u')(nl);
			const mode = u('u_bakerToonXtoon');
			const depthRange = u('u_bakerToonDepthRange');
			const detail = select(mode.lessThan(1.5),
				m.fn('toon', 'baker_xtoon_detail_depth')(positionView.z.negate(), depthRange.x, depthRange.y),
				m.fn('toon', 'baker_xtoon_detail_orientation')(N, positionViewDirection, u('u_bakerToonOrientationPower')));
			const plain = texture(ramp, vec2(toonU, 0.5)).r;
			const xtoon = texture(ramp, vec2(toonU, float(1).sub(clamp(detail, 0, 1)))).r;
			f = select(on(surface, 'toon'), vec3(select(mode.lessThan(0.5), plain, xtoon)), f);
		}
		// metal-weighted diffuse albedo with blurred normals (a metal shows no change), else the base colour
		const albedo = p.normalBlur ? diffuseContribution : diffuseColor.rgb;
		if (f !== lambert) reflectedLight.directDiffuse.addAssign(lightColor.mul(BRDF_Lambert({ diffuseColor: albedo })).mul(f.sub(lambert)));
		if (p.translucency) {
			const params = (n) => u(n);
			const tss = m.fn('translucency', 'baker_thickness_transmittance')(attribute(p.translucency.attribute, 'float'),
				params('u_bakerThAttenuation'));
			const back = m.fn('translucency', 'baker_translucency_gdc')(N, positionViewDirection, L, tss, params('u_bakerThColor'),
				params('u_bakerThDistortion'), params('u_bakerThPower'), params('u_bakerThScale'), params('u_bakerThAmbient'));
			reflectedLight.directDiffuse.addAssign(ref(surface, 'u_baker_translucency_on').mul(diffuseColor.rgb).mul(lightColor).mul(back));
		}
		if (cards) {
			const shaded = cards.shade(diffuseColor.rgb, cards.T, N, L, positionViewDirection, lightColor, cards.data.g,
				cards.data.b, 40.0, 0.1, 0.4).mul(1 / Math.PI).sub(lightColor.mul(BRDF_Lambert({ diffuseColor: diffuseColor.rgb })).mul(lambert));
			reflectedLight.directDiffuse.addAssign(select(on(surface, 'cards'), shaded, vec3(0)));
		}
		sun.push(lightColor.mul(BRDF_Lambert({ diffuseColor: diffuseColor.rgb })).mul(lambert));
	}

	// ---- after the lights (WebGL: hosts/web/surface_caustics.glsl)
	function afterLights(reflectedLight) {
		if (!p.caustics) return;
		const c = (n) => u(n);
		const world = positionWorld;
		const first = texture(tex('u_bakerCausticsFirst'), vec2(0));
		const next = texture(tex('u_bakerCausticsNext'), vec2(0));
		// the clock: the WebGL part swaps the two frames and the blend in the material's onBeforeRender, which
		// WebGPURenderer does not call; the same function runs here once a frame and the textures follow it
		const blend = uniform(0).onFrameUpdate(() => {
			surface.material.onBeforeRender?.();
			first.value = tex('u_bakerCausticsFirst');
			next.value = tex('u_bakerCausticsNext');
			return surface.uniforms.u_bakerCausticsBlend.value;
		});
		const causticsUv = m.fn('caustics', 'baker_caustics_uv')(world, c('u_bakerCausticsProjection'),
			c('u_bakerCausticsWaterLevel'), c('u_bakerCausticsDepth'), c('u_bakerCausticsTileSize'));
		const fade = m.fn('caustics', 'baker_caustics_fade')(
			m.fn('caustics', 'baker_caustics_depth')(world, c('u_bakerCausticsWaterLevel')), c('u_bakerCausticsDepth'),
			c('u_bakerCausticsFadeDistance'));
		first.uvNode = causticsUv;
		next.uvNode = causticsUv;
		const irradiance = mix(first.rgb, next.rgb, blend).mul(c('u_bakerCausticsScale'));
		const sunLight = sun.reduce((a, b) => a.add(b), vec3(0));
		const lit = m.fn('caustics', 'baker_caustics_apply')(reflectedLight.directDiffuse, sunLight, irradiance,
			c('u_bakerCausticsStrength'), fade);
		// the added light compressed into the headroom above the pixel (the indirect and specular light included)
		const other = reflectedLight.indirectDiffuse.add(reflectedLight.directSpecular).add(reflectedLight.indirectSpecular);
		const applied = m.fn('caustics', 'baker_caustics_headroom')(reflectedLight.directDiffuse, lit, other);
		reflectedLight.directDiffuse.assign(select(on(surface, 'caustics'), applied, reflectedLight.directDiffuse));
	}

	// ---- the outgoing colour (WebGL: hosts/web/surface_hatching.glsl, then the curvature view)
	const key = keyLight();
	function output(color) {
		let out = color;
		if (p.tam) {
			const finest = u('u_bakerTamFinestSize');
			// baker's stroke parameterization when the TAM names one (texCoord > 0), else TEXCOORD_0
			const tamUv = p.tam.uvAttribute ? attribute(p.tam.uvAttribute, 'vec2') : vertexUv;
			const tile = m.fn('hatching', 'baker_tam_coord')(tamUv, u('u_bakerTamScale'), finest);
			const lod = m.fn('hatching', 'baker_tam_lod')(dFdx(tile), dFdy(tile), finest, u('u_bakerTamLevels'));
			const darkness = m.fn('hatching', 'baker_hatching_darkness')(normalView, key, 1.0);
			const weights = (which) => m.custom('hatching',
				`fn baker_hatching_weight_${which}_node(darkness: f32, tonesA: vec3f, tonesB: vec3f) -> ${which === 'paper' ? 'f32' : 'vec3f'} {
	var wA: vec3f;
	var wB: vec3f;
	var wPaper: f32;
	baker_hatching_weights(darkness, tonesA, tonesB, &wA, &wB, &wPaper);
	return w${which === 'paper' ? 'Paper' : which};
}`,
				`${which === 'paper' ? 'float' : 'vec3'} baker_hatching_weight_${which}_node(float darkness, vec3 tonesA, vec3 tonesB) {
	vec3 wA;
	vec3 wB;
	float wPaper;
	baker_hatching_weights(darkness, tonesA, tonesB, wA, wB, wPaper);
	return w${which === 'paper' ? 'Paper' : which};
}`)(darkness, u('u_bakerTamTonesA'), u('u_bakerTamTonesB'));
			const a = texture(tex('u_bakerTam012'), tile).level(lod).rgb;
			const b = texture(tex('u_bakerTam345'), tile).level(lod).rgb;
			const tone = weights('paper').add(dot(weights('A'), a)).add(dot(weights('B'), b));
			out = select(on(surface, 'tam'), out.mul(tone), out);
		}
		if (p.curvature) {
			const k = clamp(attribute(p.curvature.attribute, 'float').div(u('u_bakerCurvatureScale')), -1, 1);
			const view = select(k.greaterThan(0), mix(vec3(1), vec3(0.85, 0.1, 0.05), k), mix(vec3(1), vec3(0.05, 0.2, 0.85), k.negate()))
				.mul(float(0.35).add(saturate(dot(normalView, key)).mul(0.65)));
			out = select(on(surface, 'curvature'), view, out);
		}
		return out;
	}

	// a build starts with no light summed (a material may be built for several renderers or passes)
	const begin = () => { sun.length = 0; };
	return { begin, direct, afterLights, output, key };
}

const wrapped = new Map();
/** A subclass of `Base` (a three.js node material) whose lighting and output include baker's surface nodes. */
function bakerClass(Base) {
	if (!wrapped.has(Base)) {
		wrapped.set(Base, class extends Base {
			setupLightingModel(builder) {
				const model = super.setupLightingModel(builder);
				const nodes = this.bakerNodes;
				const direct = model.direct.bind(model);
				const start = model.start.bind(model);
				model.direct = (data, b) => {
					direct(data, b);
					nodes.direct(data, b);
				};
				model.start = (b) => {
					nodes.begin();
					start(b);
					nodes.afterLights(b.context.reflectedLight);
				};
				return model;
			}

			setupOutput(builder, outputNode) {
				return super.setupOutput(builder, vec4(this.bakerNodes.output(outputNode.rgb), outputNode.a));
			}
		});
	}
	return wrapped.get(Base);
}

/** The node material drawing `material` (a GLTFLoader material with a BakerSurface) with baker's surface nodes. */
export function surfaceNodeMaterial(material, modules) {
	const surface = material.userData.bakerSurface;
	const Material = bakerClass(material.isMeshPhysicalMaterial ? MeshPhysicalNodeMaterial : MeshStandardNodeMaterial);
	const node = new Material();
	for (const key in material) {
		if (key === 'onBeforeCompile' || key === 'customProgramCacheKey' || key === 'onBeforeRender') continue;
		node[key] = material[key];
	}
	node.bakerNodes = surfaceNodes(surface, modules);
	// a node among the material's properties: WebGPURenderer refreshes the uniforms of a material without one only
	// when the material or the object changes (NodeMaterialObserver.containsNode), not when a switch flips
	node.bakerKeyLightNode = node.bakerNodes.key;
	return node;
}
