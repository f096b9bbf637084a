"""The tam bake's stroke coordinates (``--tam-strokes field``, issue 38): per mesh, a cross field aligned with the
principal curvature directions (:mod:`baker.geometry.direction_field`, Knöppel et al. 2013) and the lapped,
field-aligned parameterization of :mod:`baker.techniques.tam.stroke_parameterization` (Praun et al. 2000), written
as a new TEXCOORD set that ``BAKER_tonal_art_map.texCoord`` names, with the chart's u axis per vertex as
``_HATCHING_DIRECTION``.

Both are computed on the mesh welded across its primitives (UV, normal and primitive seams closed), so the strokes
run on across them; each primitive is then split where its vertices meet several patches: new vertex k copies
vertex ``vmap[k]`` (every attribute, morph target and primitive extension's vertex indices follow,
:func:`baker.texels.targets.reindex_primitive`), numbered in the order of the vertices they copy.

Where the field comes from, per welded vertex: an artist's combing (the ``combing`` vertex attribute, non-zero
vectors) wins; elsewhere the principal direction of k1, weighted by how clearly |k1 - k2| stands out
(:func:`~baker.geometry.direction_field.anisotropy`): the curvature bake's ``_PRINCIPAL_DIRECTION`` and
``_PRINCIPAL_CURVATURES`` when every primitive of the mesh has them (tam ``requires`` curvature, so it runs
first when both are baked), else the same estimate computed here with the curvature bake's default options.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from baker.errors import BakerError
from baker.geometry.asset import Asset
from baker.gltf.vertex_attributes import add_vertex_attribute, unpadded
from baker.techniques.tam.extension import DIRECTION_ATTRIBUTE
from baker.texels.targets import reindex_primitive

FIELD_PRINCIPAL = "principalCurvature"
FIELD_COMBED = "principalCurvatureAndCombing"
FIELD_SMOOTHEST = "smoothest"


@dataclass
class MaterialStrokes:
    """What the stroke parameterization did on one material's faces (summed over meshes)."""

    texcoord: int
    fallback_faces: int = 0
    singular_faces: int = 0
    patches: set = field(default_factory=set)  # (mesh, patch id)
    sources: set = field(default_factory=set)  # where the field came from, per mesh

    @property
    def field(self) -> str:
        """Where the field came from: combing if any mesh had it, else the principal directions if any mesh had a
        clearly anisotropic vertex, else the smoothest field."""
        return next((s for s in (FIELD_COMBED, FIELD_PRINCIPAL) if s in self.sources), FIELD_SMOOTHEST)


def welded_attribute(asset: Asset, m: int, mesh, prims: list[int], name: str, width: int) -> np.ndarray | None:
    """Vertex attribute ``name`` per welded vertex (from its first copy), or None unless every primitive has it."""
    doc = asset.doc
    values = []
    for p in prims:
        attributes = asset.meshes()[m]["primitives"][p]["attributes"]
        if name not in attributes:
            return None
        data = doc.accessor(attributes[name])
        if (data.shape[1] if data.ndim == 2 else 1) < width:
            raise BakerError(asset.source, f"tam: vertex attribute {name} of mesh {m} primitive {p} has "
                                           f"{data.shape[1] if data.ndim == 2 else 1} components, needs {width}")
        values.append(unpadded(data, width).astype(np.float64))
    values = np.concatenate(values) if len(values) > 1 else values[0]
    first = np.full(len(mesh.positions), -1, np.int64)
    first[mesh.inverse[::-1]] = np.arange(len(mesh.inverse))[::-1]
    return values[first]


def field_targets(asset: Asset, m: int, mesh, prims: list[int], faces: np.ndarray, combing: str):
    """(directions, strength, source) of the cross field's data term per welded vertex."""
    from baker.techniques.curvature import extension as curvature_ext
    from baker.geometry.direction_field import anisotropy

    direction = welded_attribute(asset, m, mesh, prims, curvature_ext.DIRECTION, 3)
    principal = welded_attribute(asset, m, mesh, prims, curvature_ext.PRINCIPAL, 2)
    if direction is None or principal is None:
        from baker.techniques.curvature.kernel import principal_curvatures
        from baker.techniques.curvature.options import CurvatureOptions

        o = CurvatureOptions()
        keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
        result = principal_curvatures(mesh.positions, faces[keep], rings=o.rings, radius=o.radius,
                                      smoothing=o.smoothing, fit=o.fit)
        direction, principal = result.direction1, np.stack([result.k1, result.k2], axis=1)
    strength = anisotropy(principal[:, 0], principal[:, 1]) * (np.linalg.norm(direction, axis=1) > 0)
    source = FIELD_PRINCIPAL if strength.any() else FIELD_SMOOTHEST
    combed = welded_attribute(asset, m, mesh, prims, combing, 3) if combing else None
    if combed is not None:
        given = np.linalg.norm(combed, axis=1) > 1e-12
        if given.any():
            direction = np.where(given[:, None], combed, direction)
            strength = np.where(given, 1.0, strength)
            source = FIELD_COMBED
    return direction, strength, source


def vertex_stroke_directions(result, normals: np.ndarray) -> np.ndarray:
    """Per split vertex of ``result``: the mean of its faces' chart u axes (all in one patch) projected onto the
    vertex normal, unit length (zero where a vertex only touches degenerate faces)."""
    total = np.zeros((len(result.vertex_map), 3))
    for corner in range(3):
        np.add.at(total, result.faces[:, corner], result.stroke_direction)
    n = normals[result.vertex_map]
    total -= n * np.einsum("ij,ij->i", total, n)[:, None]
    length = np.linalg.norm(total, axis=1)
    return np.divide(total, length[:, None], out=np.zeros_like(total), where=length[:, None] > 1e-12)


@dataclass
class MeshStrokes:
    """The stroke parameterization of one mesh's welded primitives, before it is written."""

    mesh: int
    primitives: list  # the primitives, in welding order
    face_offsets: np.ndarray  # (len(primitives) + 1,) each primitive's first face in the welded mesh
    result: object  # StrokeParameterization of the welded mesh
    vertex_direction: np.ndarray  # (split vertices, 3) ``_HATCHING_DIRECTION``
    singular: np.ndarray  # (faces,) faces around which the cross field turns
    source: str  # where the field came from


def solve_strokes(asset: Asset, groups: dict, texel_density: float, finest: int, combing: str) -> list[MeshStrokes]:
    """The cross field and stroke parameterization of every mesh of ``groups`` ({material: [(mesh, primitive)]},
    primitives with triangles), ``texel_density`` finest-level texels per mesh unit: the coordinates count TAM tiles
    (``finest`` texels each). Reads the primitives only through their welded mesh and face order, which an unwrap
    (:func:`baker.texels.targets.unwrap_material`) keeps, so the unwrap may run before, during or after this."""
    from baker.geometry.normals import vertex_normals
    from baker.geometry.direction_field import cross_field
    from baker.techniques.tam.stroke_parameterization import stroke_parameterization

    members = {mp for group in groups.values() for mp in group}
    tiles_per_unit = texel_density / finest
    out = []
    for m in sorted({m for m, _ in members}):
        prims = [p for p in asset.triangle_primitives(m) if (m, p) in members]
        mesh = asset.welded(m, prims)
        faces = np.asarray(mesh.faces, np.int64)
        normals = vertex_normals(mesh.positions, faces)
        directions, strength, source = field_targets(asset, m, mesh, prims, faces, combing)
        cross = cross_field(mesh.positions, faces, normals, directions=directions, strength=strength)
        result = stroke_parameterization(mesh.positions, faces, normals, cross.direction, scale=tiles_per_unit)
        singular = np.zeros(len(faces), bool)
        singular[cross.singular_faces] = True
        out.append(MeshStrokes(m, prims, np.cumsum([0] + [len(g.faces) for g in mesh.geometries]), result,
                               vertex_stroke_directions(result, normals), singular, source))
    return out


def write_strokes(asset: Asset, groups: dict, solved: list[MeshStrokes], direction: bool = False) -> dict:
    """Write ``solved`` (:func:`solve_strokes` of ``groups``) as the stroke TEXCOORD set (and, with ``direction``,
    ``_HATCHING_DIRECTION``) on every primitive as it is now (after an unwrap, if any). Returns {material:
    MaterialStrokes}."""
    doc = asset.doc
    material_of = {mp: material for material, members in groups.items() for mp in members}
    # one set index per material (texCoord is the material's): after every set any of its primitives has
    texcoord = {material: 1 + max(max(asset.primitive(m, p).texcoords, default=-1) for m, p in members)
                for material, members in groups.items()}
    out = {material: MaterialStrokes(texcoord[material]) for material in groups}
    for mesh in solved:
        m, result = mesh.mesh, mesh.result
        n_split = len(result.vertex_map)
        for i, p in enumerate(mesh.primitives):
            lo, hi = mesh.face_offsets[i], mesh.face_offsets[i + 1]
            strokes = out[material_of[(m, p)]]
            strokes.fallback_faces += int(result.fallback[lo:hi].sum())
            strokes.singular_faces += int(mesh.singular[lo:hi].sum())
            strokes.patches.update((m, int(k)) for k in np.unique(result.patch[lo:hi]))
            strokes.sources.add(mesh.source)
            # a new vertex per (vertex of the primitive, split vertex of the strokes) that a corner uses
            faces = asset.primitive(m, p).faces
            if len(faces) != hi - lo:
                raise AssertionError(f"tam: mesh {m} primitive {p} changed its faces since its strokes were solved")
            keys = faces.astype(np.int64) * n_split + result.faces[lo:hi]
            unique, inverse = np.unique(keys.reshape(-1), return_inverse=True)
            vmap, stroke_vertex = unique // n_split, unique % n_split
            reindex_primitive(asset, m, p, vmap, inverse.reshape(-1, 3), result.uv[stroke_vertex],
                              strokes.texcoord)
            if not direction:
                continue
            attributes = doc.json["meshes"][m]["primitives"][p]["attributes"]
            add_vertex_attribute(doc, m, attributes, DIRECTION_ATTRIBUTE, mesh.vertex_direction[stroke_vertex],
                                 leave_out="--tam-strokes uv")
    return out
