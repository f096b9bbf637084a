"""The texel engine every texture bake shares: all texture sets' texels as one stream of surface samples.

A texture bake (thickness, curvature, and whatever writes per-texel surface data next) asks :func:`gather_texels`
for the texels of every material at once: per texel its surface position, interpolated normal, tangent frame,
mesh, material and image cell, stacked over all texture sets so that one ray stream (one call, one thread pool)
covers them all. The technique computes one value per texel, and :meth:`TexelSets.images` puts the values back
into one dilated image per material.

Baking from another mesh (``asset.transfer``, ``baker bake --from HIGH``): each texel's ray also leaves the cage
toward its surface point and lands on the high mesh (:mod:`baker.texels.transfer`); :attr:`TexelSets.source` holds
where (point, normal, triangle and barycentrics for the high's per-vertex bakes), misses taking the nearest hit
texel's (:meth:`TexelSets.nearest_hits`).

Texture sizes follow the mesh unless forced (:func:`baker.texels.texture_space.size_for_density`): about
:data:`~baker.texels.texture_space.TEXELS_PER_EDGE` texels along the average triangle edge, or a given density.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np

from baker.geometry.asset import Asset, PrimitiveGeometry
from baker.texels.texture_space import AUTO_SIZE_RANGE, dilate, interpolate, window_mean
from baker.texels.targets import MaterialTarget, PrimitiveTexels, material_targets
from baker.texels.transfer import SourceHits, cage_distance, cage_positions, low_parts, project


@dataclass
class TexelSet:
    """The texels of one material's texture: ``target`` (UV set, size, primitives) and its slice of the stream."""

    target: MaterialTarget
    start: int
    stop: int

    @property
    def material(self) -> int:
        return self.target.material

    @property
    def size(self) -> int:
        return self.target.size

    @property
    def texcoord(self) -> int:
        return self.target.texcoord


@dataclass
class TexelSets:
    """Texels of every texture set, stacked: index i is one covered texel of material ``material[i]``."""

    sets: list  # of TexelSet, by material index
    positions: np.ndarray  # (n, 3) surface point at the texel centre, mesh space
    normals: np.ndarray  # (n, 3) interpolated unit normal (smooth: welded across seams when the mesh has none)
    mesh: np.ndarray  # (n,) mesh index
    material: np.ndarray  # (n,) material index
    rows: np.ndarray  # (n,) image row
    cols: np.ndarray  # (n,) image column
    # baking from another mesh (``asset.transfer``): where each texel's ray through the cage met the high mesh
    source: "SourceHits | None" = None

    def __len__(self) -> int:
        return len(self.positions)

    def tangent_frames(self) -> tuple[np.ndarray, np.ndarray]:
        """Two unit tangents per texel completing its normal to a right-handed frame."""
        from baker.geometry.frames import orthonormal_basis

        return orthonormal_basis(self.normals)

    def interpolate(self, per_vertex: Callable[[PrimitiveGeometry], np.ndarray]) -> np.ndarray:
        """Per-texel values interpolated from per-vertex ones: ``per_vertex(geometry)`` gives (vertices, ...)
        values of a primitive (as laid out for the texture: after an unwrap, vertices split along its seams)."""
        parts = []
        for texel_set in self.sets:
            for pt in texel_set.target.primitives:
                parts.append(interpolate(per_vertex(pt.geometry), pt.geometry.faces, pt.texels.triangle,
                                         pt.texels.bary))
        return np.concatenate(parts) if parts else np.zeros(0)

    def per_face(self, per_face: Callable[[MaterialTarget, PrimitiveTexels], np.ndarray]) -> np.ndarray:
        """Per-texel values of the triangle each texel lies in: ``per_face(target, primitive texels)`` gives
        (faces, ...) values of a primitive of a texture set (a UV Jacobian in ``target.texcoord``, a face normal)."""
        parts = []
        for texel_set in self.sets:
            for pt in texel_set.target.primitives:
                parts.append(per_face(texel_set.target, pt)[pt.texels.triangle])
        return np.concatenate(parts) if parts else np.zeros(0)

    def interpolate_welded(self, welded: dict) -> np.ndarray:
        """Per-texel values interpolated from per-welded-vertex ones: ``welded`` maps a mesh index to (its
        :class:`~baker.geometry.asset.WeldedMesh`, one value per welded vertex). Each primitive vertex takes the value
        of the welded vertex it was merged into: by index when the welded mesh holds the primitive as the texels
        see it, or as it was before the unwrap split its vertices (through the unwrap's vertex map); otherwise by
        position. Primitives of meshes missing give 0."""

        def per_vertex(pt: PrimitiveTexels) -> np.ndarray:
            g = pt.geometry
            if g.mesh not in welded:
                return np.zeros(len(g.positions))
            mesh, values = welded[g.mesh]
            slot = next((i for i, w in enumerate(mesh.geometries) if w.primitive == g.primitive), None)
            if slot is not None and mesh.geometries[slot] is g:
                return values[mesh.inverse[mesh.offsets[slot]: mesh.offsets[slot + 1]]]
            if slot is not None and pt.source_vertex is not None \
                    and mesh.geometries[slot].positions.shape == pt.source_positions_shape:
                return values[mesh.inverse[mesh.offsets[slot] + pt.source_vertex]]
            from scipy.spatial import cKDTree  # imported here: scipy is a large share of start-up

            _, nearest = cKDTree(mesh.positions).query(g.positions)
            return values[nearest]

        parts = [interpolate(per_vertex(pt), pt.geometry.faces, pt.texels.triangle, pt.texels.bary)
                 for texel_set in self.sets for pt in texel_set.target.primitives]
        return np.concatenate(parts) if parts else np.zeros(0)

    def window_mean(self, values: np.ndarray, include: np.ndarray, radius: int) -> tuple[np.ndarray, np.ndarray]:
        """Per texel, the mean of ``values`` over the ``include``-d texels of its own texture within ``radius``
        texels in the image that are also its neighbours on the surface of the same mesh, and that mean's squared
        standard error
        (:func:`~baker.texels.texture_space.window_mean`); NaN where there is none."""
        mean, error = np.empty(len(self), np.float64), np.empty(len(self), np.float64)
        for s in self.sets:
            part = slice(s.start, s.stop)
            mean[part], error[part] = window_mean(s.size, self.rows[part], self.cols[part], values[part],
                                                  include[part], self.positions[part], self.normals[part], radius,
                                                  self.mesh[part])
        return mean, error

    def region_edges(self, inside: np.ndarray, within_charts: bool = False) -> np.ndarray:
        """Per texel, whether it is an ``inside`` texel on the edge of that region in its image: one of its 8
        neighbours in the image is no ``inside`` texel of the same texture (or lies off the image). With every
        texel inside these are the charts' edges, which dilation copies into the padding and bilinear filtering and
        mip levels read; a window of texels around an edge texel is one-sided. ``within_charts``: only covered
        texels that are not ``inside`` count as outside (the edge of the region inside the charts, not the charts'
        own edges)."""
        edge = np.zeros(len(self), bool)
        for s in self.sets:
            rows, cols = self.rows[s.start: s.stop], self.cols[s.start: s.stop]
            # a border (and, within charts, every uncovered texel) of True or False: off the image counts as
            # outside, or not within charts
            covered = np.full((s.size + 2, s.size + 2), within_charts, bool)
            covered[rows + 1, cols + 1] = inside[s.start: s.stop]
            part = np.zeros(len(rows), bool)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    part |= ~covered[rows + 1 + dy, cols + 1 + dx]
            edge[s.start: s.stop] = part & inside[s.start: s.stop]
        return edge

    def images(self, values: np.ndarray) -> Iterator[tuple[TexelSet, np.ndarray, np.ndarray]]:
        """(texel set, image dilated past its charts, coverage mask) per material from per-texel ``values``."""
        for texel_set in self.sets:
            image = np.zeros((texel_set.size, texel_set.size) + values.shape[1:], np.float64)
            rows, cols = self.rows[texel_set.start: texel_set.stop], self.cols[texel_set.start: texel_set.stop]
            image[rows, cols] = values[texel_set.start: texel_set.stop]
            mask = np.zeros((texel_set.size, texel_set.size), bool)
            mask[rows, cols] = True
            yield texel_set, dilate(image, mask), mask

    def nearest_hits(self, hit: np.ndarray) -> np.ndarray:
        """Per texel, the texel whose source hit it takes: itself where ``hit``, else the nearest texel of its own
        texture that hit (Euclidean in the image; itself when none in its texture did)."""
        from baker.texels.texture_space import nearest_inside

        take = np.arange(len(self))
        for s in self.sets:
            part = slice(s.start, s.stop)
            rows, cols, found = self.rows[part], self.cols[part], hit[part]
            if found.all() or not found.any():
                continue
            index = np.full((s.size, s.size), -1, np.int64)
            index[rows, cols] = np.arange(s.start, s.stop)
            mask = np.zeros((s.size, s.size), bool)
            mask[rows[found], cols[found]] = True
            near_rows, near_cols = nearest_inside(mask)
            take[part] = index[near_rows[rows, cols], near_cols[rows, cols]]
        return take

    def describe(self) -> str:
        """The chosen sizes, for progress lines: ``material 0 256², material 3 1024²``."""
        return ", ".join(f"material {s.material} {s.size}²" for s in self.sets)


def gather_texels(asset: Asset, size: int | None = None, density: float | None = None, seed: int = 0,
                  layouts: dict | None = None, auto_range: tuple[int, int] = AUTO_SIZE_RANGE) -> TexelSets:
    """Texels of every material's texture (layouts chosen or unwrapped by
    :func:`baker.texels.targets.material_targets`): ``size`` forces the width and height, else ``density``
    texels per mesh unit, else the automatic density (its size within ``auto_range``). ``layouts`` ({material: (texcoord, size)}) bakes only those
    materials, in the UV set and size given."""
    sets, positions, normals, mesh, material, rows, cols, cages = [], [], [], [], [], [], [], []
    start = 0
    request = asset.transfer
    for target in material_targets(asset, size, seed, density=density, layouts=layouts, auto_range=auto_range):
        for pt in target.primitives:
            g, t = pt.geometry, pt.texels
            positions.append(interpolate(g.positions, g.faces, t.triangle, t.bary))
            if request is not None:
                distance = cage_distance(request, asset) if request.cage is None else 0.0
                cages.append(interpolate(cage_positions(request, g, pt.source_vertex, distance), g.faces,
                                         t.triangle, t.bary))
            normals.append(interpolate(pt.normals, g.faces, t.triangle, t.bary))
            mesh.append(np.full(len(t.rows), g.mesh, np.int64))
            material.append(np.full(len(t.rows), target.material, np.int64))
            rows.append(t.rows)
            cols.append(t.cols)
        stop = start + sum(len(pt.texels.rows) for pt in target.primitives)
        sets.append(TexelSet(target, start, stop))
        start = stop

    def stack(parts, shape):
        return np.concatenate(parts) if parts else np.zeros(shape)

    normals_all = stack(normals, (0, 3))
    normals_all = normals_all / np.maximum(np.linalg.norm(normals_all, axis=1, keepdims=True), 1e-30)
    texels = TexelSets(sets, stack(positions, (0, 3)), normals_all, stack(mesh, 0).astype(np.int64),
                       stack(material, 0).astype(np.int64), stack(rows, 0).astype(np.int64),
                       stack(cols, 0).astype(np.int64))
    if request is not None:
        texels.source = project(request, texels.positions, stack(cages, (0, 3)), texels.nearest_hits,
                                low_parts(request, asset)[texels.mesh] if len(texels) else None)
    return texels
