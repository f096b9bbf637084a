"""The WGSL test cases: every function of every ``runtime-shaders/baker_*.wgsl`` module on random inputs, with its
numpy twin (``tests/gl/twins_*.py``, the same twins the GLSL renders are checked against) as the reference.

Inputs are drawn from a fixed seed over each function's domain (unit vectors where the GLSL asks for unit vectors,
positive widths and exponents, ...). ``tolerance`` per case is (absolute, relative): float32 arithmetic agrees to a
few ulp; the cases that go through a transcendental with a large argument or a texture filter say why they need
more.
"""
from __future__ import annotations

import math

import numpy as np

from . import (twins_caustics, twins_edges, twins_fur, twins_hair, twins_hair_cards, twins_hair_shading, twins_hatching,
               twins_normal_blur, twins_skin, twins_text, twins_toon, twins_translucency)
from .wgsl import Case, Texture

N = 1024  # samples per case (a multiple of the fragment harness's row width)
F32 = np.float32


class Inputs:
    """Random float32 inputs, reproducible: one generator per module."""

    def __init__(self, seed: int):
        self.rng = np.random.default_rng(seed)

    def uniform(self, low, high, width=None, n=N):
        shape = (n,) if width is None else (n, width)
        return self.rng.uniform(low, high, shape).astype(F32)

    def unit(self, n=N):
        v = self.rng.normal(size=(n, 3))
        return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(F32)

    def integers(self, low, high, n=N):
        return self.rng.integers(low, high, n).astype(F32)


def pow_tolerance(exponent):
    """pow(x, p) is exp2(p log2(x)) on a GPU: the rounding of log2 comes out p times larger."""
    return (1e-6, 4e-6 + 2.5e-7 * exponent)


POW_WHY = "pow(x, p) = exp2(p log2 x): log2's rounding grows p-fold"


# ------------------------------------------------------------------------------------------------ translucency
def translucency_cases():
    r = Inputs(1)
    tw = twins_translucency
    N_, V, L = r.unit(), r.unit(), r.unit()
    texel = r.uniform(0, 1, 4)
    thickness, factor, distance = r.uniform(-0.2, 2.0), r.uniform(0.1, 3), r.uniform(0.05, 2)
    tss, color, power = r.uniform(0, 1), r.uniform(0, 1, 3), r.uniform(0.5, 12)
    distortion, scale, ambient = r.uniform(0, 1), r.uniform(0, 3), r.uniform(0, 0.5)
    params = np.concatenate([distance[:, None], distortion[:, None], power[:, None], scale[:, None],
                             ambient[:, None], color], axis=1)
    struct = ("BakerThickness(p[0], p[1], p[2], p[3], p[4], vec3f(p[5], p[6], p[7]))")
    return [
        Case("translucency", "baker_thickness_from_texture", [("texel", "vec4f"), ("factor", "f32")], "f32",
             {"texel": texel, "factor": factor}, lambda i: tw.baker_thickness_from_texture(i["texel"], i["factor"]),
             call="baker_thickness_from_texture(texel, factor)"),
        Case("translucency", "baker_thickness_transmittance", [("thickness", "f32"), ("distance", "f32")], "f32",
             {"thickness": thickness, "distance": distance},
             lambda i: tw.baker_thickness_transmittance(i["thickness"], i["distance"]),
             call="baker_thickness_transmittance(thickness, distance)"),
        Case("translucency", "baker_translucency_rtr",
             [("V", "vec3f"), ("L", "vec3f"), ("tss", "f32"), ("color", "vec3f"), ("power", "f32")], "vec3f",
             {"V": V, "L": L, "tss": tss, "color": color, "power": power},
             lambda i: tw.baker_translucency_rtr(i["V"], i["L"], i["tss"], i["color"], i["power"]),
             call="baker_translucency_rtr(V, L, tss, color, power)"),
        Case("translucency", "baker_translucency_gdc",
             [("N", "vec3f"), ("V", "vec3f"), ("L", "vec3f"), ("tss", "f32"), ("color", "vec3f"),
              ("distortion", "f32"), ("power", "f32"), ("scale", "f32"), ("ambient", "f32")], "vec3f",
             {"N": N_, "V": V, "L": L, "tss": tss, "color": color, "distortion": distortion, "power": power,
              "scale": scale, "ambient": ambient},
             lambda i: tw.baker_translucency_gdc(i["N"], i["V"], i["L"], i["tss"], i["color"], i["distortion"],
                                                 i["power"], i["scale"], i["ambient"]),
             call="baker_translucency_gdc(N, V, L, tss, color, distortion, power, scale, ambient)"),
        Case("translucency", "baker_translucency",
             [("N", "vec3f"), ("V", "vec3f"), ("L", "vec3f"), ("thickness", "f32"), ("p0", "vec4f"),
              ("p1", "vec4f")], "vec3f",
             {"N": N_, "V": V, "L": L, "thickness": thickness, "p0": params[:, :4], "p1": params[:, 4:]},
             lambda i: tw.baker_translucency(
                 {"attenuationDistance": i["p0"][:, 0], "distortion": i["p0"][:, 1], "power": i["p0"][:, 2],
                  "scale": i["p0"][:, 3], "ambient": i["p1"][:, 0], "subsurfaceColor": i["p1"][:, 1:]},
                 i["N"], i["V"], i["L"], i["thickness"]),
             body="    let p = array<f32, 8>(p0.x, p0.y, p0.z, p0.w, p1.x, p1.y, p1.z, p1.w);\n"
                  f"    let result: vec3f = baker_translucency({struct}, N, V, L, thickness);"),
    ]


# ------------------------------------------------------------------------------------------------ edges
def edges_cases():
    r = Inputs(2)
    tw = twins_edges
    v0, v1 = r.uniform(-1, 1, 3), r.uniform(-1, 1, 3)
    v2, v3, eye = r.uniform(-1, 1, 3), r.uniform(-1, 1, 3), r.uniform(-4, 4, 3)
    flags = r.integers(0, 64)
    crease = r.uniform(-1, 1)
    w0, w1 = r.uniform(0.5, 3), r.uniform(0.5, 3)
    clip0 = np.concatenate([r.uniform(-2, 2, 3), w0[:, None]], 1)
    clip1 = np.concatenate([r.uniform(-2, 2, 3), w1[:, None]], 1)
    clip1[:64] = clip0[:64]  # a zero-length edge on screen: the fallback direction
    corner, width, viewport = r.integers(0, 4), r.uniform(0.5, 6), r.uniform(64, 2048, 2)
    bary = r.uniform(0, 1, 3)
    slope, mask = r.uniform(0, 0.05, 3), r.integers(0, 8)
    halo = r.uniform(0, 3)
    return [
        Case("edges", "baker_fin_classify",
             [("v0", "vec3f"), ("v1", "vec3f"), ("v2", "vec3f"), ("v3", "vec3f"), ("flags", "f32"),
              ("eye", "vec3f"), ("creaseCos", "f32")], "i32",
             {"v0": v0, "v1": v1, "v2": v2, "v3": v3, "flags": flags, "eye": eye, "creaseCos": crease},
             lambda i: tw.baker_fin_classify(i["v0"], i["v1"], i["v2"], i["v3"], i["flags"], i["eye"],
                                             i["creaseCos"]),
             call="baker_fin_classify(v0, v1, v2, v3, flags, eye, creaseCos)"),
        Case("edges", "baker_fin_position",
             [("clip0", "vec4f"), ("clip1", "vec4f"), ("corner", "f32"), ("width", "f32"), ("viewport", "vec2f")],
             "vec4f", {"clip0": clip0, "clip1": clip1, "corner": corner, "width": width, "viewport": viewport},
             lambda i: tw.baker_fin_position(i["clip0"], i["clip1"], i["corner"], i["width"][:, None],
                                             i["viewport"]),
             call="baker_fin_position(clip0, clip1, corner, width, viewport)"),
        Case("edges", "baker_fin_culled", [], "vec4f", {"none": np.zeros((N, 0), F32)},
             lambda i: np.broadcast_to(tw.baker_fin_culled(), (N, 4)), call="baker_fin_culled()"),
        Case("edges", "baker_shell_position",
             [("position", "vec3f"), ("normal", "vec3f"), ("clipW", "f32"), ("width", "f32"),
              ("height", "f32"), ("scaleY", "f32")], "vec3f",
             {"position": v0, "normal": r.unit(), "clipW": w0, "width": width, "height": viewport[:, 1],
              "scaleY": r.uniform(0.3, 3)},
             lambda i: tw.baker_shell_position(i["position"], i["normal"], i["clipW"], i["width"], i["height"],
                                               i["scaleY"]),
             call="baker_shell_position(position, normal, clipW, width, height, scaleY)"),
        Case("edges", "baker_barycentric", [("vertexId", "i32")], "vec3f", {"vertexId": r.integers(0, 100000)},
             lambda i: tw.baker_barycentric(i["vertexId"].astype(np.int64)), call="baker_barycentric(vertexId)"),
        Case("edges", "baker_wireframe_distance", [("bary", "vec3f"), ("slope", "vec3f"), ("mask", "i32")], "f32",
             {"bary": bary, "slope": slope, "mask": mask},
             lambda i: tw.baker_wireframe_distance(i["bary"], i["slope"], i["mask"].astype(np.int64)),
             call="baker_wireframe_distance(bary, slope, mask)"),
        Case("edges", "baker_wireframe",
             [("bary", "vec3f"), ("slope", "vec3f"), ("mask", "i32"), ("width", "f32"), ("halo", "f32")], "vec2f",
             {"bary": bary, "slope": slope, "mask": mask, "width": width, "halo": halo},
             lambda i: tw.baker_wireframe(i["bary"], i["slope"], i["mask"].astype(np.int64), i["width"], i["halo"]),
             call="baker_wireframe(bary, slope, mask, width, halo)"),
    ]


# ------------------------------------------------------------------------------------------------ fur
def fur_cases():
    r = Inputs(3)
    tw = twins_fur
    shell, count = r.integers(0, 32), r.integers(1, 33)
    position, normal, displacement = r.uniform(-1, 1, 3), r.unit(), r.uniform(-0.1, 0.1, 3)
    spacing, tiling = r.uniform(0.0005, 0.01), r.uniform(0.5, 40)
    v0, v1, v2, v3 = (r.uniform(-1, 1, 3) for _ in range(4))
    corner, length = r.integers(0, 4), r.uniform(0.001, 0.05)
    height, occlusion = r.uniform(0, 1), r.uniform(0, 1)
    # the fin weight at thresholds the baker writes (0.2-0.6) and far beyond; n0 + n1 never vanishes
    n0, n1 = r.unit(), r.unit()
    n1 = np.where((np.sum(n0 * n1, 1) < -0.9)[:, None], -n1, n1)
    return [
        Case("fur", "baker_fur_shell_height", [("shell", "f32"), ("count", "f32")], "f32",
             {"shell": shell, "count": count}, lambda i: tw.baker_fur_shell_height(i["shell"], i["count"]),
             call="baker_fur_shell_height(shell, count)"),
        Case("fur", "baker_fur_shell_position",
             [("position", "vec3f"), ("normal", "vec3f"), ("shell", "f32"), ("spacing", "f32"), ("count", "f32"),
              ("displacement", "vec3f")], "vec3f",
             {"position": position, "normal": normal, "shell": shell, "spacing": spacing, "count": count,
              "displacement": displacement},
             lambda i: tw.baker_fur_shell_position(i["position"], i["normal"], i["shell"], i["spacing"], i["count"],
                                                   i["displacement"]),
             call="baker_fur_shell_position(position, normal, shell, spacing, count, displacement)"),
        Case("fur", "baker_fur_shell_uv", [("uv", "vec2f"), ("tiling", "f32")], "vec2f",
             {"uv": r.uniform(0, 1, 2), "tiling": tiling},
             lambda i: tw.baker_fur_shell_uv(i["uv"], i["tiling"][:, None]), call="baker_fur_shell_uv(uv, tiling)"),
        Case("fur", "baker_fur_shell_shade", [("texel", "vec4f"), ("height", "f32"), ("occlusion", "f32")], "vec4f",
             {"texel": r.uniform(0, 1, 4), "height": height, "occlusion": occlusion},
             lambda i: tw.baker_fur_shell_shade(i["texel"], i["height"], i["occlusion"]),
             call="baker_fur_shell_shade(texel, height, occlusion)"),
        Case("fur", "baker_fur_fin_face_normals",
             [("v0", "vec3f"), ("v1", "vec3f"), ("v2", "vec3f"), ("v3", "vec3f")], "mat3x3f",
             {"v0": v0, "v1": v1, "v2": v2, "v3": v3},
             lambda i: np.concatenate([*tw.baker_fur_fin_face_normals(i["v0"], i["v1"], i["v2"], i["v3"]),
                                       np.zeros((N, 3), F32)], 1),
             body="    var n0: vec3f;\n    var n1: vec3f;\n    baker_fur_fin_face_normals(v0, v1, v2, v3, &n0, &n1);\n"
                  "    let result = mat3x3f(n0, n1, vec3f(0.0));"),
        Case("fur", "baker_fur_fin_position",
             [("v0", "vec3f"), ("v1", "vec3f"), ("normal", "vec3f"), ("corner", "f32"), ("length", "f32")], "vec3f",
             {"v0": v0, "v1": v1, "normal": normal, "corner": corner, "length": length},
             lambda i: tw.baker_fur_fin_position(i["v0"], i["v1"], i["normal"], i["corner"], i["length"]),
             call="baker_fur_fin_position(v0, v1, normal, corner, length)"),
        Case("fur", "baker_fur_fin_weight", [("n0", "vec3f"), ("n1", "vec3f"), ("V", "vec3f"), ("threshold", "f32")],
             "f32", {"n0": n0, "n1": n1, "V": r.unit(), "threshold": r.uniform(0.05, 1)},
             lambda i: tw.baker_fur_fin_weight(i["n0"], i["n1"], i["V"], i["threshold"]),
             call="baker_fur_fin_weight(n0, n1, V, threshold)"),
    ]


# ------------------------------------------------------------------------------------------------ hair
def constant(value, n=N):
    """A per-sample input that is the same for every sample (for twins that take that argument as a number)."""
    return np.full(n, value, F32)


def hair_cases():
    r = Inputs(4)
    tw = twins_hair
    T, L, V, N_ = r.unit(), r.unit(), r.unit(), r.unit()
    position, eye = r.uniform(-1, 1, 3), r.uniform(-3, 3, 3)
    eye[:32] = position[:32] + T[:32] * 2.0  # looking straight along the strand: the fallback side vector
    colors = [r.uniform(0, 1, 3) for _ in range(3)]
    cases = [
        Case("hair", "baker_hair_width", [("root", "f32"), ("tip", "f32"), ("param", "f32"), ("scale", "f32")],
             "f32", {"root": r.uniform(1e-4, 1e-3), "tip": r.uniform(0, 1e-4), "param": r.uniform(0, 1),
                     "scale": r.uniform(0.5, 1.5)},
             lambda i: tw.baker_hair_width(i["root"], i["tip"], i["param"], i["scale"]),
             call="baker_hair_width(root, tip, param, scale)"),
        Case("hair", "baker_hair_pixel_size", [("distance", "f32"), ("tanHalf", "f32"), ("height", "f32")], "f32",
             {"distance": r.uniform(0.1, 20), "tanHalf": r.uniform(0.1, 1.5), "height": r.integers(64, 4096)},
             lambda i: tw.baker_hair_pixel_size(i["distance"], i["tanHalf"], i["height"]),
             call="baker_hair_pixel_size(distance, tanHalf, height)"),
        Case("hair", "baker_hair_coverage", [("width", "f32"), ("pixel", "f32")], "vec2f",
             {"width": r.uniform(0, 2e-3), "pixel": r.uniform(0, 2e-3)},
             lambda i: tw.baker_hair_coverage(i["width"], i["pixel"]), call="baker_hair_coverage(width, pixel)"),
        Case("hair", "baker_hair_ribbon_side", [("position", "vec3f"), ("tangent", "vec3f"), ("eye", "vec3f")],
             "vec3f", {"position": position, "tangent": T, "eye": eye},
             lambda i: tw.baker_hair_ribbon_side(i["position"], i["tangent"], i["eye"]),
             call="baker_hair_ribbon_side(position, tangent, eye)"),
        Case("hair", "baker_hair_ribbon_position",
             [("position", "vec3f"), ("tangent", "vec3f"), ("eye", "vec3f"), ("width", "f32"), ("side", "f32")],
             "vec3f", {"position": position, "tangent": T, "eye": eye, "width": r.uniform(0, 1e-3),
                       "side": r.integers(0, 2)},
             lambda i: tw.baker_hair_ribbon_position(i["position"], i["tangent"], i["eye"], i["width"], i["side"]),
             call="baker_hair_ribbon_position(position, tangent, eye, width, side)"),
        Case("hair", "baker_hair_offset_child",
             [("root", "vec3f"), ("weights", "vec3f")] + [(f"{k}{j}", "vec3f") for j in range(3)
                                                          for k in ("g", "r")], "vec3f",
             {"root": position, "weights": r.uniform(0, 1, 3),
              **{f"{k}{j}": r.uniform(-1, 1, 3) for j in range(3) for k in ("g", "r")}},
             lambda i: tw.baker_hair_offset_child(i["root"], i["weights"], i["g0"], i["r0"], i["g1"], i["r1"],
                                                  i["g2"], i["r2"]),
             call="baker_hair_offset_child(root, weights, g0, r0, g1, r1, g2, r2)"),
        Case("hair", "baker_hair_lod_index_count", [("strands", "i32"), ("vertices", "i32")], "i32",
             {"strands": r.integers(0, 20000), "vertices": r.integers(2, 64)},
             lambda i: tw.baker_hair_lod_index_count(i["strands"], i["vertices"]),
             call="baker_hair_lod_index_count(strands, vertices)"),
        Case("hair", "baker_hair_lod_width", [("width", "f32"), ("scale", "f32")], "f32",
             {"width": r.uniform(0, 1e-3), "scale": r.uniform(1, 4)},
             lambda i: tw.baker_hair_lod_width(i["width"], i["scale"]), call="baker_hair_lod_width(width, scale)"),
        Case("hair", "baker_hair_gaussian", [("beta", "f32"), ("x", "f32")], "f32",
             {"beta": r.uniform(1e-3, 1), "x": r.uniform(-2, 2)},
             lambda i: np.array([tw.baker_hair_gaussian(b, x) for b, x in zip(i["beta"], i["x"])]),
             call="baker_hair_gaussian(beta, x)"),
        Case("hair", "baker_hair_fresnel", [("cosTheta", "f32")], "f32", {"cosTheta": r.uniform(-0.2, 1.2)},
             lambda i: tw.baker_hair_fresnel(i["cosTheta"]), call="baker_hair_fresnel(cosTheta)"),
    ]
    for exponent in (1.0, 8.0, 80.0):
        cases += [
            Case("hair", "baker_hair_kajiya_kay",
                 [("T", "vec3f"), ("L", "vec3f"), ("V", "vec3f"), ("diffuse", "vec3f"), ("specular", "vec3f"),
                  ("exponent", "f32")], "vec3f",
                 {"T": T, "L": L, "V": V, "diffuse": colors[0], "specular": colors[1], "exponent": constant(exponent)},
                 lambda i, e=exponent: tw.baker_hair_kajiya_kay(i["T"], i["L"], i["V"], i["diffuse"], i["specular"], e),
                 call="baker_hair_kajiya_kay(T, L, V, diffuse, specular, exponent)", label=f"p={exponent:g}",
                 tolerance=pow_tolerance(exponent), why=POW_WHY),
            Case("hair", "baker_hair_strand_specular",
                 [("T", "vec3f"), ("V", "vec3f"), ("L", "vec3f"), ("exponent", "f32")], "f32",
                 {"T": T, "V": V, "L": L, "exponent": constant(exponent)},
                 lambda i, e=exponent: tw.baker_hair_strand_specular(i["T"], i["V"], i["L"], e),
                 call="baker_hair_strand_specular(T, V, L, exponent)", label=f"p={exponent:g}",
                 tolerance=pow_tolerance(exponent), why=POW_WHY),
        ]
    for shift1, shift2 in ((0.0, 0.0), (-0.1, 0.15), (0.3, -0.25)):
        cases += [
            Case("hair", "baker_hair_shift_tangent", [("T", "vec3f"), ("N", "vec3f"), ("shift", "f32")], "vec3f",
                 {"T": T, "N": N_, "shift": constant(shift1)},
                 lambda i, s=shift1: tw.baker_hair_shift_tangent(i["T"], i["N"], s),
                 call="baker_hair_shift_tangent(T, N, shift)", label=f"shift={shift1:g}"),
            Case("hair", "baker_hair_scheuermann",
                 [("T", "vec3f"), ("N", "vec3f"), ("V", "vec3f"), ("L", "vec3f"), ("base", "vec3f"),
                  ("spec1", "vec3f"), ("spec2", "vec3f"), ("shifts", "vec2f"), ("exponents", "vec2f"),
                  ("mask", "f32")], "vec3f",
                 {"T": T, "N": N_, "V": V, "L": L, "base": colors[0], "spec1": colors[1], "spec2": colors[2],
                  "shifts": np.tile(F32([shift1, shift2]), (N, 1)), "exponents": np.tile(F32([60, 12]), (N, 1)),
                  "mask": r.uniform(0, 1)},
                 lambda i, s1=shift1, s2=shift2: tw.baker_hair_scheuermann(
                     i["T"], i["N"], i["V"], i["L"], i["base"], i["spec1"], i["spec2"], s1, s2, 60.0, 12.0, i["mask"]),
                 call="baker_hair_scheuermann(T, N, V, L, base, spec1, spec2, shifts.x, shifts.y, exponents.x, "
                      "exponents.y, mask)", label=f"shifts={shift1:g},{shift2:g}"),
        ]
    for roughness, shift in ((0.2, 0.035), (0.5, 0.0), (0.9, -0.05)):
        cases.append(Case(
            "hair", "baker_hair_marschner",
            [("T", "vec3f"), ("V", "vec3f"), ("L", "vec3f"), ("base", "vec3f"), ("roughness", "f32"), ("shift", "f32")],
            "vec3f", {"T": T, "V": V, "L": L, "base": r.uniform(0.05, 1, 3), "roughness": constant(roughness),
                      "shift": constant(shift)},
            lambda i, a=roughness, s=shift: tw.baker_hair_marschner(i["T"], i["V"], i["L"], i["base"], a, s),
            call="baker_hair_marschner(T, V, L, base, roughness, shift)", label=f"r={roughness:g}",
            tolerance=(1e-4, 1e-3),
            why="SwiftShader's asin and cos put up to 2e-4 into cos thetaD (within WGSL's accuracy: asin inherits "
                "atan2's 4096 ulp, cos is 2^-11 absolute), and pow(base, 1.6 / cos thetaD) magnifies it"))
    return cases


# ------------------------------------------------------------------------------------------------ hair cards
def hair_cards_cases():
    r = Inputs(5)
    tw = twins_hair_cards
    normal = r.uniform(-1, 1, 3)
    tangent = np.concatenate([r.uniform(-1, 1, 3), np.where(r.uniform(0, 1) < 0.5, -1, 1)[:, None]], 1).astype(F32)
    flow = r.uniform(0, 1, 3)
    flow[:32] = 0.5  # a zero flow: the bitangent fallback
    dpdx, dpdy, duvdx, duvdy = r.uniform(-1, 1, 3), r.uniform(-1, 1, 3), r.uniform(-1, 1, 2), r.uniform(-1, 1, 2)
    T, L, V = r.unit(), r.unit(), r.unit()
    cases = [
        Case("hair_cards", "baker_hair_cards_cut", [("alpha", "f32"), ("cutoff", "f32")], "bool",
             {"alpha": r.uniform(0, 1), "cutoff": constant(0.5)},
             lambda i: tw.baker_hair_cards_cut(i["alpha"], 0.5), call="baker_hair_cards_cut(alpha, cutoff)"),
        Case("hair_cards", "baker_hair_cards_flow", [("flow", "vec3f"), ("normal", "vec3f"), ("tangent", "vec4f")],
             "vec3f", {"flow": flow, "normal": normal, "tangent": tangent},
             lambda i: tw.baker_hair_cards_flow(i["flow"], i["normal"], i["tangent"]),
             call="baker_hair_cards_flow(flow, normal, tangent)", tolerance=(1e-5, 4e-6),
             why="w / |w| magnifies the rounding of w where the flow texel is near 0.5 (|w| small)"),
        Case("hair_cards", "baker_hair_cards_frame",
             [("N", "vec3f"), ("dpdx", "vec3f"), ("dpdy", "vec3f"), ("duvdx", "vec2f"), ("duvdy", "vec2f")], "vec4f",
             {"N": r.unit(), "dpdx": dpdx, "dpdy": dpdy, "duvdx": duvdx, "duvdy": duvdy},
             lambda i: tw.baker_hair_cards_frame(i["N"], i["dpdx"], i["dpdy"], i["duvdx"], i["duvdy"]),
             call="baker_hair_cards_frame(N, dpdx, dpdy, duvdx, duvdy)"),
    ]
    for depth_range in (0.002, 0.05):
        cases += [
            Case("hair_cards", "baker_hair_cards_depth", [("texel", "f32"), ("range", "f32")], "f32",
                 {"texel": r.uniform(0, 1), "range": constant(depth_range)},
                 lambda i, d=depth_range: tw.baker_hair_cards_depth(i["texel"], d),
                 call="baker_hair_cards_depth(texel, range)", label=f"range={depth_range:g}"),
            Case("hair_cards", "baker_hair_cards_displace",
                 [("position", "vec3f"), ("normal", "vec3f"), ("texel", "f32"), ("range", "f32")], "vec3f",
                 {"position": r.uniform(-1, 1, 3), "normal": normal, "texel": r.uniform(0, 1),
                  "range": constant(depth_range)},
                 lambda i, d=depth_range: tw.baker_hair_cards_displace(i["position"], i["normal"], i["texel"], d),
                 call="baker_hair_cards_displace(position, normal, texel, range)", label=f"range={depth_range:g}"),
        ]
    for exponent, shift, root_shade in ((8.0, 0.0, 1.0), (60.0, 0.1, 0.4), (200.0, -0.2, 0.0)):
        cases.append(Case(
            "hair_cards", "baker_hair_cards_shade",
            [("base", "vec3f"), ("T", "vec3f"), ("N", "vec3f"), ("L", "vec3f"), ("V", "vec3f"), ("light", "vec3f"),
             ("rootToTip", "f32"), ("random", "f32"), ("params", "vec3f")], "vec3f",
            {"base": r.uniform(0, 1, 3), "T": T, "N": normal, "L": L, "V": V, "light": r.uniform(0, 3, 3),
             "rootToTip": r.uniform(-0.2, 1.2), "random": r.uniform(0, 1),
             "params": np.tile(F32([exponent, shift, root_shade]), (N, 1))},
            lambda i, e=exponent, s=shift, o=root_shade: tw.baker_hair_cards_shade(
                i["base"], i["T"], i["N"], i["L"], i["V"], i["light"], i["rootToTip"], i["random"], e, s, o),
            call="baker_hair_cards_shade(base, T, N, L, V, light, rootToTip, random, params.x, params.y, params.z)",
            label=f"p={exponent:g}", tolerance=pow_tolerance(exponent), why=POW_WHY))
    return cases


# ------------------------------------------------------------------------------------------------ skin
def skin_cases():
    r = Inputs(6)
    tw = twins_skin
    N_, L = r.unit(), r.unit()
    # a detail normal within 60 degrees of the smooth one, as a normal map tilts it
    Nd = N_ + 0.9 * r.unit()
    Nd = (Nd / np.linalg.norm(Nd, axis=1, keepdims=True)).astype(F32)
    lut = Texture("lut", [r.uniform(0, 1, None, n=24 * 40 * 4).reshape(24, 40, 4)])
    penumbra = Texture("penumbraLut", [r.uniform(0, 1, None, n=16 * 20 * 4).reshape(16, 20, 4)])
    curvature_range, width_range = (0.0, 2.0), (0.5, 8.0)
    ndotl, curvature = r.uniform(-1.2, 1.2), r.uniform(-0.3, 2.4)
    blend = np.tile(F32([0.9, 0.5, 0.3]), (N, 1))
    skin = {"curvatureRange": curvature_range, "curvatureScale": 0.01, "normalBlend": (0.9, 0.5, 0.3)}
    struct = ("BakerSkin(vec2f(0.0, 2.0), 0.01, vec2f(0.5, 8.0), vec3f(0.9, 0.5, 0.3), 0.2, 0.3, "
              "vec3f(0.8, 0.2, 0.1))")
    mesh_curvature = r.uniform(-50, 250)
    linear = r.uniform(-2, 2, 9)
    direction = r.uniform(-1, 1, 3)
    direction[:16] = 0  # a vanished direction stays zero
    sampled = dict(stage="fragment", tolerance=(2e-6, 4e-6))
    return [
        Case("skin", "baker_skin_lut_coord", [("t", "f32"), ("size", "f32")], "f32",
             {"t": r.uniform(-0.2, 1.2), "size": r.integers(2, 512)},
             lambda i: tw.baker_skin_lut_coord(i["t"], i["size"]), call="baker_skin_lut_coord(t, size)"),
        Case("skin", "baker_skin_curvature", [("k", "f32"), ("scale", "f32")], "f32",
             {"k": mesh_curvature, "scale": r.uniform(1e-3, 1)},
             lambda i: tw.baker_skin_curvature(i["k"], i["scale"]), call="baker_skin_curvature(k, scale)"),
        Case("skin", "baker_skin_curvature_from_derivatives", [("dN", "vec3f"), ("dP", "vec3f")], "f32",
             {"dN": r.uniform(0, 0.1, 3), "dP": r.uniform(1e-4, 1e-2, 3)},
             lambda i: tw.baker_skin_curvature_from_derivatives(i["dN"], i["dP"]),
             call="baker_skin_curvature_from_derivatives(dN, dP)"),
        Case("skin", "baker_skin_curvature_along_light",
             [("principal", "vec2f"), ("direction", "vec3f"), ("N", "vec3f"), ("L", "vec3f")], "f32",
             {"principal": np.sort(r.uniform(-50, 200, 2), 1)[:, ::-1], "direction": direction, "N": N_, "L": L},
             lambda i: tw.baker_skin_curvature_along_light(i["principal"], i["direction"], i["N"], i["L"]),
             call="baker_skin_curvature_along_light(principal, direction, N, L)"),
        Case("skin", "baker_skin_direction_to", [("linear", "mat3x3f"), ("direction", "vec3f")], "vec3f",
             {"linear": linear, "direction": direction},
             # WGSL's mat3x3f is read column by column: column c = linear[3c:3c+3], so the twin's matrix is its T
             lambda i: np.stack([tw.baker_skin_direction_to(m.reshape(3, 3).T, d)
                                 for m, d in zip(i["linear"], i["direction"])]),
             call="baker_skin_direction_to(linear, direction)"),
        Case("skin", "baker_skin_lut_uv", [("ndotl", "f32"), ("curvature", "f32"), ("size", "vec2f")], "vec2f",
             {"ndotl": ndotl, "curvature": curvature, "size": r.integers(2, 256, n=2 * N).reshape(N, 2)},
             lambda i: tw.baker_skin_lut_uv(i["ndotl"], i["curvature"], curvature_range,
                                            (i["size"][:, 0], i["size"][:, 1])),
             call="baker_skin_lut_uv(ndotl, curvature, vec2f(0.0, 2.0), size)"),
        Case("skin", "baker_skin_lut", [("ndotl", "f32"), ("curvature", "f32")], "vec3f",
             {"ndotl": ndotl, "curvature": curvature},
             lambda i: tw.baker_skin_lut(lut.levels[0], i["ndotl"], i["curvature"], curvature_range),
             call="baker_skin_lut(lut, lutSampler, ndotl, curvature, vec2f(0.0, 2.0))", textures=[lut], **sampled),
        Case("skin", "baker_skin_blended_ndotl",
             [("Nsmooth", "vec3f"), ("Ndetail", "vec3f"), ("L", "vec3f"), ("blend", "vec3f")], "vec3f",
             {"Nsmooth": N_, "Ndetail": Nd, "L": L, "blend": blend},
             lambda i: tw.baker_skin_blended_ndotl(i["Nsmooth"], i["Ndetail"], i["L"], (0.9, 0.5, 0.3)),
             call="baker_skin_blended_ndotl(Nsmooth, Ndetail, L, blend)"),
        Case("skin", "baker_skin_lut_rgb", [("ndotl", "vec3f"), ("curvature", "f32")], "vec3f",
             {"ndotl": r.uniform(-1, 1, 3), "curvature": curvature},
             lambda i: tw.baker_skin_lut_rgb(lut.levels[0], i["ndotl"], i["curvature"], curvature_range),
             call="baker_skin_lut_rgb(lut, lutSampler, ndotl, curvature, vec2f(0.0, 2.0))", textures=[lut], **sampled),
        Case("skin", "baker_skin_penumbra", [("shadow", "f32"), ("width", "f32")], "vec3f",
             {"shadow": r.uniform(-0.1, 1.1), "width": r.uniform(0.05, 3)},
             lambda i: tw.baker_skin_penumbra(penumbra.levels[0], i["shadow"], i["width"], width_range),
             call="baker_skin_penumbra(penumbraLut, penumbraLutSampler, shadow, width, vec2f(0.5, 8.0))",
             textures=[penumbra], **sampled),
        Case("skin", "baker_skin_wrap", [("ndotl", "f32"), ("wrap", "f32"), ("width", "f32"), ("color", "vec3f")],
             "vec3f", {"ndotl": ndotl, "wrap": r.uniform(0, 1), "width": r.uniform(0.05, 0.5),
                       "color": r.uniform(0, 1, 3)},
             lambda i: tw.baker_skin_wrap(i["ndotl"], i["wrap"], i["width"], i["color"]),
             call="baker_skin_wrap(ndotl, wrap, width, color)"),
        Case("skin", "baker_skin_diffuse",
             [("Nsmooth", "vec3f"), ("Ndetail", "vec3f"), ("L", "vec3f"), ("k", "f32")], "vec3f",
             {"Nsmooth": N_, "Ndetail": Nd, "L": L, "k": mesh_curvature},
             lambda i: tw.baker_skin_diffuse(skin, lut.levels[0], i["Nsmooth"], i["Ndetail"], i["L"], i["k"]),
             call=f"baker_skin_diffuse({struct}, lut, lutSampler, Nsmooth, Ndetail, L, k)", textures=[lut],
             stage="fragment", tolerance=(1e-5, 4e-6),
             why="the LUT's texels are random: an ulp of N.L moves the sample 1e-7 texel, worth up to 1e-5 in value"),
        Case("skin", "baker_skin_diffuse_normals", [("ndotl", "vec3f"), ("k", "f32")], "vec3f",
             {"ndotl": r.uniform(-1, 1, 3), "k": mesh_curvature},
             lambda i: tw.baker_skin_diffuse_normals(skin, lut.levels[0], i["ndotl"], i["k"]),
             call=f"baker_skin_diffuse_normals({struct}, lut, lutSampler, ndotl, k)", textures=[lut], **sampled),
    ]


# ------------------------------------------------------------------------------------------------ toon
def toon_cases():
    r = Inputs(7)
    tw = twins_toon
    ramp = Texture("ramp", [r.uniform(0, 1, None, n=1 * 64 * 4).reshape(1, 64, 4)])
    xmap = Texture("xtoonMap", [r.uniform(0, 1, None, n=16 * 32 * 4).reshape(16, 32, 4)])
    ndotl, rgb = r.uniform(-1.2, 1.2), r.uniform(0, 1, 3)
    rgb[:8] = [[0.2, 0.2, 0.2], [0, 0, 0], [1, 1, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0], [0, 0.3, 0.3]]
    cases = [
        Case("toon", "baker_toon_u", [("ndotl", "f32")], "f32", {"ndotl": ndotl},
             lambda i: tw.baker_toon_u(i["ndotl"]), call="baker_toon_u(ndotl)"),
        Case("toon", "baker_toon_ramp", [("ndotl", "f32")], "f32", {"ndotl": ndotl},
             lambda i: tw.baker_toon_ramp(ramp.levels[0], i["ndotl"]), call="baker_toon_ramp(ramp, rampSampler, ndotl)",
             textures=[ramp], stage="fragment"),
        Case("toon", "baker_xtoon_detail_depth", [("z", "f32"), ("zMin", "f32"), ("zMax", "f32")], "f32",
             {"z": r.uniform(0.05, 60), "zMin": constant(0.5), "zMax": constant(40.0)},
             lambda i: tw.baker_xtoon_detail_depth(i["z"], 0.5, 40.0), call="baker_xtoon_detail_depth(z, zMin, zMax)"),
        Case("toon", "baker_xtoon", [("ndotl", "f32"), ("detail", "f32")], "f32",
             {"ndotl": ndotl, "detail": r.uniform(-0.1, 1.1)},
             lambda i: tw.baker_xtoon(xmap.levels[0], i["ndotl"], i["detail"]),
             call="baker_xtoon(xtoonMap, xtoonMapSampler, ndotl, detail)", textures=[xmap], stage="fragment"),
        Case("toon", "baker_rgb_to_hsv", [("rgb", "vec3f")], "vec3f", {"rgb": rgb},
             lambda i: tw.baker_rgb_to_hsv(i["rgb"]), call="baker_rgb_to_hsv(rgb)"),
        Case("toon", "baker_hsv_to_rgb", [("hsv", "vec3f")], "vec3f", {"hsv": r.uniform(0, 1, 3)},
             lambda i: tw.baker_hsv_to_rgb(i["hsv"]), call="baker_hsv_to_rgb(hsv)"),
    ]
    for exponent in (0.5, 2.0, 8.0):
        cases.append(Case(
            "toon", "baker_xtoon_detail_orientation", [("N", "vec3f"), ("V", "vec3f"), ("r", "f32")], "f32",
            {"N": r.unit(), "V": r.unit(), "r": constant(exponent)},
            lambda i, e=exponent: tw.baker_xtoon_detail_orientation(i["N"], i["V"], e),
            call="baker_xtoon_detail_orientation(N, V, r)", label=f"r={exponent:g}", tolerance=pow_tolerance(exponent),
            why=POW_WHY))
    for bands, softness, shadow in ((2.0, 0.0, 0.3), (4.0, 0.0, 0.0), (3.0, 0.2, 0.25), (5.0, 0.6, 0.1)):
        cases.append(Case(
            "toon", "baker_toon_bands", [("u", "f32"), ("params", "vec3f")], "f32",
            {"u": r.uniform(-0.1, 1.1), "params": np.tile(F32([bands, softness, shadow]), (N, 1))},
            lambda i, b=bands, s=softness, o=shadow: tw.baker_toon_bands(i["u"], b, s, o),
            call="baker_toon_bands(u, params.x, params.y, params.z)", label=f"bands={bands:g},softness={softness:g}"))
    for levels in (2.0, 4.0, 7.0):
        cases += [
            Case("toon", "baker_quantize", [("x", "f32"), ("levels", "f32")], "f32",
                 {"x": r.uniform(0, 1), "levels": constant(levels)},
                 lambda i, n=levels: tw.baker_quantize(i["x"], n), call="baker_quantize(x, levels)",
                 label=f"levels={levels:g}"),
            Case("toon", "baker_posterize_hsv", [("rgb", "vec3f"), ("levels", "f32")], "vec3f",
                 {"rgb": rgb, "levels": constant(levels)},
                 lambda i, n=levels: tw.baker_posterize_hsv(i["rgb"], n), call="baker_posterize_hsv(rgb, levels)",
                 label=f"levels={levels:g}"),
            Case("toon", "baker_posterize_ycbcr", [("rgb", "vec3f"), ("levels", "f32")], "vec3f",
                 {"rgb": rgb, "levels": constant(levels)},
                 lambda i, n=levels: tw.baker_posterize_ycbcr(i["rgb"], n), call="baker_posterize_ycbcr(rgb, levels)",
                 label=f"levels={levels:g}"),
        ]
    return cases


# ------------------------------------------------------------------------------------------------ caustics
def caustics_cases():
    r = Inputs(8)
    tw = twins_caustics
    first = Texture("first", [r.uniform(0, 1, None, n=16 * 16 * 4).reshape(16, 16, 4)], address="repeat")
    following = Texture("next", [r.uniform(0, 1, None, n=16 * 16 * 4).reshape(16, 16, 4)], address="repeat")
    world = r.uniform(-3, 3, 3)
    direction = np.concatenate([r.uniform(-0.4, 0.4, 2), -r.uniform(0.6, 1, 1)], 1)[:, [0, 2, 1]]
    direction = (direction / np.linalg.norm(direction, axis=1, keepdims=True)).astype(F32)
    cases = [
        Case("caustics", "baker_caustics_frame", [("time", "f32"), ("period", "f32"), ("count", "f32")], "vec3f",
             {"time": r.uniform(0, 40), "period": constant(4.0), "count": constant(16.0)},
             lambda i: tw.baker_caustics_frame(i["time"], 4.0, 16.0), call="baker_caustics_frame(time, period, count)"),
        Case("caustics", "baker_caustics_depth", [("world", "vec3f"), ("water", "f32")], "f32",
             {"world": world, "water": r.uniform(-1, 2)},
             lambda i: tw.baker_caustics_depth(i["world"], i["water"]), call="baker_caustics_depth(world, water)"),
        Case("caustics", "baker_caustics_uv", [("world", "vec3f"), ("direction", "vec3f"), ("params", "vec3f")],
             "vec2f", {"world": world, "direction": direction, "params": np.tile(F32([1.5, 1.5, 0.8]), (N, 1))},
             lambda i: tw.baker_caustics_uv(i["world"], i["direction"], 1.5, 1.5, 0.8),
             call="baker_caustics_uv(world, direction, params.x, params.y, params.z)"),
        Case("caustics", "baker_caustics_fade", [("pointDepth", "f32"), ("depth", "f32"), ("fade", "f32")], "f32",
             {"pointDepth": r.uniform(-1, 4), "depth": constant(1.5), "fade": constant(1.0)},
             lambda i: tw.baker_caustics_fade(i["pointDepth"], 1.5, 1.0),
             call="baker_caustics_fade(pointDepth, depth, fade)"),
        Case("caustics", "baker_caustics_apply",
             [("lit", "vec3f"), ("sun", "vec3f"), ("irradiance", "vec3f"), ("strength", "f32"), ("fade", "f32")],
             "vec3f", {"lit": r.uniform(0, 1, 3), "sun": r.uniform(0, 1, 3), "irradiance": r.uniform(0, 4, 3),
                       "strength": constant(0.8), "fade": r.uniform(0, 1)},
             lambda i: tw.baker_caustics_apply(i["lit"], i["sun"], i["irradiance"], 0.8, i["fade"]),
             call="baker_caustics_apply(lit, sun, irradiance, strength, fade)"),
    ]
    for rgb in (0.0, 1.0):
        cases.append(Case(
            "caustics", "baker_caustics_irradiance",
            [("uv", "vec2f"), ("blend", "f32"), ("scale", "f32"), ("rgb", "f32")], "vec3f",
            {"uv": r.uniform(-3, 3, 2), "blend": r.uniform(0, 1), "scale": constant(2.5), "rgb": constant(rgb)},
            lambda i, c=rgb: tw.baker_caustics_irradiance(first.levels[0], following.levels[0], i["uv"], i["blend"],
                                                          2.5, c),
            call="baker_caustics_irradiance(first, firstSampler, next, nextSampler, uv, blend, scale, rgb)",
            textures=[first, following], stage="fragment", label=f"rgb={rgb:g}"))
    return cases


# ------------------------------------------------------------------------------------------------ normal blur
def _hemisphere_texels(r):
    """Normal-map texels 0.5 + 0.5 n of unit normals n tilted at most ~70 degrees off +Z, as normal maps hold."""
    n = r.unit()
    n[:, 2] = np.abs(n[:, 2]) + 0.35
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return (0.5 + 0.5 * n).astype(F32)


def _columns(m):
    """(n, 9) column-major floats (as WGSL reads a mat3x3f) -> (n, 3, 3) matrices, [row, column]."""
    return np.asarray(m, F32).reshape(-1, 3, 3).transpose(0, 2, 1)


def normal_blur_cases():
    r = Inputs(9)
    tw = twins_normal_blur
    size = 32
    irradiance = Texture("irradiance", [r.uniform(0, 1, None, n=size * size * 4).reshape(size, size, 4)])
    stretch = Texture("stretchTexture", [r.uniform(0.2, 1, None, n=size * size * 4).reshape(size, size, 4)])
    N_, L = r.unit(), r.unit()
    # an orthonormal-ish frame: T, B perpendicular to N, as a host passes it
    T = np.cross(N_, r.unit())
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    B = np.cross(N_, T)
    tbn = np.concatenate([T, B, N_], 1).astype(F32)
    texels = [_hemisphere_texels(r) for _ in range(3)]
    cases = [
        Case("normal_blur", "baker_normal_blur_derivative_frame",
             [("N", "vec3f"), ("dPdx", "vec3f"), ("dPdy", "vec3f"), ("dUVdx", "vec2f"), ("dUVdy", "vec2f")], "mat3x3f",
             {"N": N_, "dPdx": r.uniform(-0.01, 0.01, 3), "dPdy": r.uniform(-0.01, 0.01, 3),
              "dUVdx": r.uniform(-0.01, 0.01, 2), "dUVdy": r.uniform(-0.01, 0.01, 2)},
             lambda i: tw.baker_normal_blur_derivative_frame(i["N"], i["dPdx"], i["dPdy"], i["dUVdx"], i["dUVdy"])
             .transpose(0, 2, 1).reshape(N, 9),
             call="baker_normal_blur_derivative_frame(N, dPdx, dPdy, dUVdx, dUVdy)"),
        Case("normal_blur", "baker_normal_blur_ndotl",
             [("nRed", "vec3f"), ("nGreen", "vec3f"), ("nBlue", "vec3f"), ("L", "vec3f")], "vec3f",
             {"nRed": r.unit(), "nGreen": r.unit(), "nBlue": r.unit(), "L": L},
             lambda i: tw.baker_normal_blur_ndotl(i["nRed"], i["nGreen"], i["nBlue"], i["L"]),
             call="baker_normal_blur_ndotl(nRed, nGreen, nBlue, L)"),
        Case("normal_blur", "baker_normal_blur_stretch", [("uv", "vec2f"), ("scale", "f32")], "vec2f",
             {"uv": r.uniform(-0.1, 1.1, 2), "scale": constant(0.3)},
             lambda i: tw.baker_normal_blur_stretch(stretch.levels[0], i["uv"], 0.3),
             call="baker_normal_blur_stretch(stretchTexture, stretchTextureSampler, uv, scale)", textures=[stretch],
             stage="fragment"),
        Case("normal_blur", "baker_normal_blur_uv_position", [("uv", "vec2f")], "vec4f", {"uv": r.uniform(0, 1, 2)},
             # WebGPU's framebuffer row 0 is at NDC y = +1 (GL's at -1): the WGSL flips y so that the target's texel
             # (u, v) is still the textures' texel (u, v), the meaning the GLSL has
             lambda i: tw.baker_normal_blur_uv_position(i["uv"]) * F32([1, -1, 1, 1]),
             call="baker_normal_blur_uv_position(uv)"),
        Case("normal_blur", "baker_normal_blur_tsd_accumulate",
             [("total", "vec3f"), ("blurred", "vec3f"), ("weights", "vec3f")], "vec3f",
             {"total": r.uniform(0, 2, 3), "blurred": r.uniform(0, 1, 3), "weights": r.uniform(0, 1, 3)},
             lambda i: tw.baker_normal_blur_tsd_accumulate(i["total"], i["blurred"], i["weights"]),
             call="baker_normal_blur_tsd_accumulate(total, blurred, weights)"),
    ]
    for flip in (1.0, -1.0):
        cases += [
            Case("normal_blur", "baker_normal_blur_decode", [("texel", "vec3f"), ("flipY", "f32")], "vec3f",
                 {"texel": texels[0], "flipY": constant(flip)},
                 lambda i, f=flip: tw.baker_normal_blur_decode(i["texel"], f),
                 call="baker_normal_blur_decode(texel, flipY)",
                 label=f"flipY={flip:g}"),
            Case("normal_blur", "baker_normal_blur_lambert",
                 [("tbn", "mat3x3f"), ("red", "vec3f"), ("green", "vec3f"), ("blue", "vec3f"), ("L", "vec3f"),
                  ("flipY", "f32")], "vec3f",
                 {"tbn": tbn, "red": texels[0], "green": texels[1], "blue": texels[2], "L": L, "flipY": constant(flip)},
                 lambda i, f=flip: tw.baker_normal_blur_lambert(_columns(i["tbn"]), i["red"], i["green"], i["blue"],
                                                                i["L"], f),
                 call="baker_normal_blur_lambert(tbn, red, green, blue, L, flipY)", label=f"flipY={flip:g}"),
            Case("normal_blur", "baker_normal_blur_blend_ndotl",
                 [("tbn", "mat3x3f"), ("smoothed", "vec3f"), ("blend", "vec3f"), ("L", "vec3f"), ("flipY", "f32")],
                 "vec3f", {"tbn": tbn, "smoothed": texels[1], "blend": np.tile(F32([0.7, 0.4, 0.2]), (N, 1)), "L": L,
                           "flipY": constant(flip)},
                 lambda i, f=flip: tw.baker_normal_blur_blend_ndotl(_columns(i["tbn"]), i["smoothed"], (0.7, 0.4, 0.2),
                                                                    i["L"], f),
                 call="baker_normal_blur_blend_ndotl(tbn, smoothed, blend, L, flipY)", label=f"flipY={flip:g}"),
        ]
    for sigma in (0.002, 0.02):
        cases.append(Case(
            "normal_blur", "baker_normal_blur_tsd_step", [("uv", "vec2f"), ("direction", "vec2f"), ("params", "vec2f")],
            "vec3f", {"uv": r.uniform(0, 1, 2), "direction": np.eye(2, dtype=F32)[r.rng.integers(0, 2, N)],
                      "params": np.tile(F32([sigma, 0.3]), (N, 1))},
            lambda i, g=sigma: tw.baker_normal_blur_tsd_step(irradiance.levels[0], stretch.levels[0], i["uv"],
                                                             i["direction"], g, 0.3),
            call="baker_normal_blur_tsd_step(irradiance, irradianceSampler, stretchTexture, stretchTextureSampler, uv, "
                 "direction, params.x, params.y)", textures=[irradiance, stretch], stage="fragment",
            label=f"sigma={sigma:g}"))
    return cases


# ------------------------------------------------------------------------------------------------ hatching
def hatching_cases():
    r = Inputs(10)
    tw = twins_hatching
    levels_a = [r.uniform(0, 1, None, n=s * s * 4).reshape(s, s, 4) for s in (32, 16, 8, 4)]
    levels_b = [r.uniform(0, 1, None, n=s * s * 4).reshape(s, s, 4) for s in (32, 16, 8, 4)]
    tone_count = 8
    volume = [r.uniform(0, 1, None, n=tone_count * s * s * 4).reshape(tone_count, s, s, 4) for s in (16, 8, 4)]
    tam_a, tam_b = Texture("tones012", levels_a, address="repeat"), Texture("tones345", levels_b, address="repeat")
    tam = Texture("tam", volume, address="repeat", dimension="2d-array")
    tones_a, tones_b = (0.12, 0.25, 0.4), (0.55, 0.7, 0.86)
    darkness = r.uniform(-0.1, 1.1)
    tile, lod = r.uniform(-2, 2, 2), r.uniform(-0.5, 3.5)
    return [
        Case("hatching", "baker_tam_coord", [("uv", "vec2f"), ("scale", "f32"), ("finest", "f32")], "vec2f",
             {"uv": r.uniform(0, 1, 2), "scale": constant(96.0), "finest": constant(256.0)},
             lambda i: tw.baker_tam_coord(i["uv"], 96.0, 256.0), call="baker_tam_coord(uv, scale, finest)"),
        Case("hatching", "baker_tam_lod", [("dx", "vec2f"), ("dy", "vec2f"), ("finest", "f32"), ("levels", "f32")],
             "f32", {"dx": r.uniform(-0.05, 0.05, 2), "dy": r.uniform(-0.05, 0.05, 2), "finest": constant(256.0),
                     "levels": constant(6.0)},
             lambda i: tw.baker_tam_lod(i["dx"], i["dy"], 256.0, 6.0), call="baker_tam_lod(dx, dy, finest, levels)"),
        Case("hatching", "baker_hatching_weights", [("darkness", "f32")], "mat3x3f", {"darkness": darkness},
             lambda i: np.concatenate([w.reshape(N, -1) for w in tw.baker_hatching_weights(i["darkness"], tones_a,
                                                                                           tones_b)]
                                      + [np.zeros((N, 2), F32)], 1),
             body="    var wA: vec3f;\n    var wB: vec3f;\n    var wPaper: f32;\n"
                  f"    baker_hatching_weights(darkness, vec3f{tones_a}, vec3f{tones_b}, &wA, &wB, &wPaper);\n"
                  "    let result = mat3x3f(wA, wB, vec3f(wPaper, 0.0, 0.0));"),
        Case("hatching", "baker_hatching", [("tile", "vec2f"), ("lod", "f32"), ("darkness", "f32")], "f32",
             {"tile": tile, "lod": lod, "darkness": darkness},
             lambda i: tw.baker_hatching(levels_a, levels_b, i["tile"], i["lod"], i["darkness"], tones_a, tones_b),
             call=f"baker_hatching(tones012, tones012Sampler, tones345, tones345Sampler, tile, lod, darkness, "
                  f"vec3f{tones_a}, vec3f{tones_b})", textures=[tam_a, tam_b]),
        Case("hatching", "baker_hatching_volume", [("tile", "vec2f"), ("lod", "f32"), ("darkness", "f32")], "f32",
             {"tile": tile, "lod": r.uniform(-0.5, 2.5), "darkness": darkness},
             lambda i: tw.baker_hatching_volume([level[..., 0] for level in volume], i["tile"], i["lod"],
                                                i["darkness"], tone_count, 0.9),
             call=f"baker_hatching_volume(tam, tamSampler, tile, lod, darkness, {tone_count}.0, 0.9)",
             textures=[tam]),
        Case("hatching", "baker_hatching_darkness", [("N", "vec3f"), ("L", "vec3f"), ("intensity", "f32")], "f32",
             {"N": r.unit(), "L": r.unit(), "intensity": r.uniform(0, 2)},
             lambda i: tw.baker_hatching_darkness(i["N"], i["L"], i["intensity"]),
             call="baker_hatching_darkness(N, L, intensity)"),
    ]


# ------------------------------------------------------------------------------------------------ text
def text_cases():
    r = Inputs(11)
    tw = twins_text
    texel, shadow = r.uniform(0, 1, 4), r.uniform(0, 1, 4)
    # texels near the edge, where the coverage ramps
    texel[: N // 2] = 0.5 + (texel[: N // 2] - 0.5) * 0.1
    px_range = r.uniform(1, 12)
    cases = [
        Case("text", "baker_text_median", [("v", "vec3f")], "f32", {"v": texel[:, :3]},
             lambda i: tw.baker_text_median(i["v"]), call="baker_text_median(v)"),
        Case("text", "baker_text_screen_px_range", [("range", "f32"), ("atlas", "vec2f"), ("fw", "vec2f")], "f32",
             {"range": r.uniform(2, 8), "atlas": r.integers(64, 4096, n=2 * N).reshape(N, 2),
              "fw": r.uniform(0, 0.01, 2)},
             lambda i: tw.baker_text_screen_px_range(i["range"][:, None], i["atlas"], i["fw"]),
             call="baker_text_screen_px_range(range, atlas, fw)"),
        Case("text", "baker_text_coverage", [("d", "f32"), ("px", "f32")], "f32",
             {"d": r.uniform(-0.5, 0.5), "px": px_range},
             lambda i: tw.baker_text_coverage(i["d"], i["px"]), call="baker_text_coverage(d, px)"),
        Case("text", "baker_text_msdf_opacity", [("msd", "vec3f"), ("px", "f32")], "f32",
             {"msd": texel[:, :3], "px": px_range},
             lambda i: tw.baker_text_msdf_opacity(i["msd"], i["px"]), call="baker_text_msdf_opacity(msd, px)"),
        Case("text", "baker_text_over", [("src", "vec4f"), ("dst", "vec4f")], "vec4f",
             {"src": r.uniform(0, 1, 4), "dst": r.uniform(0, 1, 4)},
             lambda i: tw.baker_text_over(i["src"], i["dst"]), call="baker_text_over(src, dst)"),
    ]
    styles = [
        {"color": (1, 1, 1, 1), "softness": 0.0, "outlineColor": (0, 0, 0, 1), "outlineWidth": 0.0,
         "glowColor": (0, 0, 0, 0), "glowWidth": 0.0, "shadowColor": (0, 0, 0, 0), "shadowSoftness": 0.0},
        {"color": (0.9, 0.8, 0.2, 0.9), "softness": 1.5, "outlineColor": (0.1, 0.2, 0.6, 1), "outlineWidth": 2.0,
         "glowColor": (1, 0.5, 0, 0.7), "glowWidth": 3.0, "shadowColor": (0, 0, 0, 0.6), "shadowSoftness": 1.0},
    ]
    for field in range(4):
        cases += [
            Case("text", "baker_text_edge_distance", [("texel", "vec4f"), ("fieldType", "i32")], "f32",
                 {"texel": texel, "fieldType": constant(field)},
                 lambda i, t=field: tw.baker_text_edge_distance(i["texel"], t),
                 call="baker_text_edge_distance(texel, fieldType)", label=f"type={field}"),
            Case("text", "baker_text_true_distance", [("texel", "vec4f"), ("fieldType", "i32")], "f32",
                 {"texel": texel, "fieldType": constant(field)},
                 lambda i, t=field: tw.baker_text_true_distance(i["texel"], t),
                 call="baker_text_true_distance(texel, fieldType)", label=f"type={field}"),
        ]
        for k, style in enumerate(styles):
            values = [*style["color"], style["softness"], *style["outlineColor"], style["outlineWidth"],
                      *style["glowColor"], style["glowWidth"], *style["shadowColor"], style["shadowSoftness"]]
            struct = ("BakerTextStyle(vec4f({}, {}, {}, {}), {}, vec4f({}, {}, {}, {}), {}, vec4f({}, {}, {}, {}), {}, "
                      "vec4f({}, {}, {}, {}), {})").format(*(f"{float(v):.9g}" for v in values))
            cases.append(Case(
                "text", "baker_text_shade",
                [("texel", "vec4f"), ("shadowTexel", "vec4f"), ("fieldType", "i32"), ("range", "f32"), ("px", "f32")],
                "vec4f", {"texel": texel, "shadowTexel": shadow, "fieldType": constant(field), "range": constant(4.0),
                          "px": px_range},
                lambda i, t=field, st=style: tw.baker_text_shade(st, i["texel"], i["shadowTexel"], t, 4.0, i["px"]),
                call=f"baker_text_shade({struct}, texel, shadowTexel, fieldType, range, px)",
                label=f"type={field},style={k}"))
    return cases


# ------------------------------------------------------------------------------------------------ hair shading
def hair_shading_cases():
    """The fibre tables of ``baker hair-lut`` (beta 0.3, half-float texels) and Zinke's dual-scattering table,
    sampled in a compute pass (textureSampleLevel) at random fibres, lights, views, melanins and fibre counts."""
    from baker.techniques.hair_shading.dual import dual_table_for
    from baker.techniques.hair_shading.tables import as_half, bake_tables

    r = Inputs(12)
    tw = twins_hair_shading
    tables = as_half(bake_tables(0.3, 0.3, 1.55))
    dual = dual_table_for(0.3, 0.3, 1.55, 2.0)
    h = tw.params(tables, dual)
    m_rgba = np.concatenate([tables.longitudinal, np.zeros(tables.longitudinal.shape[:2] + (1,), F32)], 2)
    m_tex, n_tex, d_tex = Texture("mTable", [m_rgba]), Texture("nTable", [tables.azimuthal]), Texture("dualTable",
                                                                                                      [dual.table])
    struct = ("BakerHairShading(vec4f({:.9g}, {:.9g}, {:.9g}, {:.9g}), {:.9g}, {:.9g}, {:.9g}, {:.9g}, 1.0, 1.0)"
              .format(*h["variances"], h["tilt"], float(h["slices"]), h["alphaF"], h["betaF"]))
    T, L, V = r.unit(), r.unit(), r.unit()
    crossed = r.rng.choice([0.0, 0.0, 0.4, 1.0, 2.0, 3.0, 5.0, 9.0], N).astype(F32)
    sigma = tw.baker_hair_shading_melanin(r.rng.choice([0.0, 0.3, 1.3, 8.0], N), r.uniform(0, 0.5)).astype(F32)
    theta_i, theta_o = r.uniform(-1.5, 1.5), r.uniform(-1.5, 1.5)
    phi, x = r.uniform(0, math.pi), r.uniform(0, 1)
    sampled = "the GPU's bilinear weights on half-float texels of narrow lobes"
    lobes = "the dual-scattering lobes: WGSL's sin and cos are exact to 2^-11 absolute only, divided by v"
    return [
        Case("hair_shading", "baker_hair_shading_melanin", [("eu", "f32"), ("pheo", "f32")], "vec3f",
             {"eu": r.uniform(0, 8), "pheo": r.uniform(0, 2)},
             lambda i: tw.baker_hair_shading_melanin(i["eu"], i["pheo"]), call="baker_hair_shading_melanin(eu, pheo)",
             tolerance=(1e-6, 1e-6)),
        Case("hair_shading", "baker_hair_shading_absorption", [("sigma", "vec3f")], "vec3f", {"sigma": sigma},
             lambda i: tw.baker_hair_shading_absorption(i["sigma"]), call="baker_hair_shading_absorption(sigma)",
             tolerance=(1e-6, 1e-5), why="exp"),
        Case("hair_shading", "baker_hair_shading_angles", [("T", "vec3f"), ("L", "vec3f"), ("V", "vec3f")], "vec3f",
             {"T": T, "L": L, "V": V}, lambda i: tw.baker_hair_shading_angles(i["T"], i["L"], i["V"]),
             call="baker_hair_shading_angles(T, L, V)", tolerance=(5e-4, 1e-5),
             why="acos and asin near +-1 keep half of float32's digits"),
        Case("hair_shading", "baker_hair_shading_longitudinal",
             [("thetaI", "f32"), ("thetaO", "f32"), ("tilt", "f32")], "vec4f",
             {"thetaI": theta_i, "thetaO": theta_o, "tilt": constant(h["tilt"])},
             lambda i: tw.baker_hair_shading_longitudinal(m_rgba, i["thetaI"], i["thetaO"], h["tilt"]),
             call="baker_hair_shading_longitudinal(mTable, mTableSampler, thetaI, thetaO, tilt)", textures=[m_tex],
             tolerance=(1e-4, 1e-4), why=sampled),
        Case("hair_shading", "baker_hair_shading_azimuthal",
             [("slices", "f32"), ("phi", "f32"), ("thetaO", "f32"), ("x", "f32")], "vec4f",
             {"slices": constant(tables.slices), "phi": phi, "thetaO": theta_o, "x": x},
             lambda i: tw.baker_hair_shading_azimuthal(tables.azimuthal, tables.slices, i["phi"], i["thetaO"], i["x"]),
             call="baker_hair_shading_azimuthal(nTable, nTableSampler, slices, phi, thetaO, x)", textures=[n_tex],
             tolerance=(1e-6, 1e-4), why=sampled),
        Case("hair_shading", "baker_hair_shading_single",
             [("T", "vec3f"), ("L", "vec3f"), ("V", "vec3f"), ("sigma", "vec3f")], "vec3f",
             {"T": T, "L": L, "V": V, "sigma": sigma},
             lambda i: tw.baker_hair_shading_single(m_rgba, tables.azimuthal, h, i["T"], i["L"], i["V"], i["sigma"]),
             call=f"baker_hair_shading_single(mTable, mTableSampler, nTable, nTableSampler, {struct}, T, L, V, sigma)",
             textures=[m_tex, n_tex], tolerance=(1e-4, 1e-3), why=sampled + "; acos and asin near +-1"),
        Case("hair_shading", "baker_hair_shading_log_i0", [("x", "f32")], "f32", {"x": r.uniform(0, 300)},
             lambda i: tw.baker_hair_shading_log_i0(i["x"]), call="baker_hair_shading_log_i0(x)",
             tolerance=(1e-5, 1e-6), why="x - log(x) / 2 + log(series) in float32"),
        Case("hair_shading", "baker_hair_shading_lobe", [("thetaI", "f32"), ("thetaO", "f32"), ("v", "f32")], "f32",
             {"thetaI": theta_i, "thetaO": theta_o, "v": r.uniform(0.04, 0.6)},  # hair_shade's: v_TT + beta_f^2 up
             lambda i: tw.baker_hair_shading_lobe(i["thetaI"], i["thetaO"], i["v"]),
             call="baker_hair_shading_lobe(thetaI, thetaO, v)", tolerance=(1e-6, 2e-2),
             why="WGSL's sin and cos are exact to 2^-11 absolute only, and the exponent divides them by v"),
        Case("hair_shading", "baker_hair_shading_dual", [("theta", "f32"), ("x", "f32")], "vec4f",
             {"theta": theta_o, "x": x}, lambda i: tw.baker_hair_shading_dual(dual.table, i["theta"], i["x"]),
             call="baker_hair_shading_dual(dualTable, dualTableSampler, theta, x)", textures=[d_tex],
             tolerance=(1e-6, 1e-4), why=sampled),
        Case("hair_shading", "baker_hair_shading",
             [("T", "vec3f"), ("L", "vec3f"), ("V", "vec3f"), ("crossed", "f32"), ("sigma", "vec3f")], "vec3f",
             {"T": T, "L": L, "V": V, "crossed": crossed, "sigma": sigma},
             lambda i: tw.baker_hair_shading(m_rgba, tables.azimuthal, dual.table, h, i["T"], i["L"], i["V"],
                                             i["crossed"], i["sigma"]),
             call=(f"baker_hair_shading(mTable, mTableSampler, nTable, nTableSampler, dualTable, dualTableSampler, "
                   f"{struct}, T, L, V, crossed, sigma)"),
             textures=[m_tex, n_tex, d_tex], tolerance=(1e-3, 1e-2), why=lobes),
    ]


def all_cases():
    return [*translucency_cases(), *edges_cases(), *fur_cases(), *hair_cases(), *hair_cards_cases(),
            *hair_shading_cases(),
            *skin_cases(), *toon_cases(), *caustics_cases(), *normal_blur_cases(), *hatching_cases(), *text_cases()]
