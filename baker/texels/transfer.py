"""Baking from another mesh: texels (and vertices) of a low mesh find the high mesh's surface through a cage.

As Substance, Marmoset Toolbag, xNormal and Blender Cycles' "Selected to Active" do: a ray leaves the cage (a mesh
with the low's topology, or the low surface pushed out along its smoothed normals by the cage distance) toward the
low surface point and goes on as far again behind it; the first high surface it meets is the texel's sample. The
hit carries the high's point, its interpolated smooth normal and the triangle and barycentrics that interpolate any
per-vertex bake of the high (computed once per high mesh and cached by content hash, :meth:`SourceMesh.per_vertex`).
Texels whose ray meets nothing take the hit of the nearest texel of their texture that found one (the misses are
counted, :attr:`SourceHits.misses`). When the source holds several named meshes, a low mesh ``NAME_low`` traces only
the part ``NAME_high`` (:func:`low_parts`), in a scene of its own.

The cage distance, when not given, follows the two meshes: rays from the low's vertices and triangle centres along
both senses of its normals meet the high at its distance from the low; a robust maximum of those (the 99.5th
percentile of those within :data:`MAX_OFFSET` of the low's bounding-box diagonal: rays through a hole of the high
cross the shape) times :data:`CAGE_MARGIN`, plus :data:`CAGE_FLOOR` of the low's bounding-box diagonal.
"""
from __future__ import annotations

import hashlib
import os
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from baker.errors import BakerError

CAGE_QUANTILE = 0.995  # a robust maximum of the high's distance from the low: a few stray spikes are misses
CAGE_MARGIN = 1.25  # the cage lies this far beyond that distance
CAGE_FLOOR = 0.002  # ... plus this share of the low's bounding-box diagonal (a high lying on the low: distance 0)
MAX_OFFSET = 0.1  # share of the low's bounding-box diagonal: farther hits along its normals are not the high's offset
OVERLAP_FRACTION = 0.5  # fewer texels than this share meeting the high: the source is not the low's shape
TRACE_CHUNK = 65536  # rays per task of the thread pool


@dataclass
class TransferRequest:
    """What ``--from``, ``--cage`` and ``--cage-distance`` ask for, with the meshes read."""

    source_path: Path
    source: "SourceMesh"
    cage_path: Path | None = None
    cage: dict | None = None  # (mesh, primitive) -> (vertices, 3) cage positions, the low's own topology
    cage_distance: float | None = None  # mesh units; None: automatic (:func:`automatic_cage_distance`)
    summary: dict = field(default_factory=dict)  # what the bakes found (misses, cage distance), for extras


def part_name(name, suffix: str) -> str | None:
    """A mesh's part: its name without the ``_low``/``_high`` suffix (case-insensitive), as the anchors and
    Substance/Marmoset match low and high parts; None for a mesh without a name."""
    if not isinstance(name, str) or not name:
        return None
    return name[: -len(suffix)] if name.lower().endswith(suffix) else name


class SourceMesh:
    """The high mesh: every triangle primitive of every mesh, each mesh welded (one vertex per position), as one
    triangle soup in mesh space, with area-weighted smooth vertex normals and one Embree scene; ``parts`` maps a
    part name (:func:`part_name`) to its triangles when the file holds several named meshes."""

    def __init__(self, positions: np.ndarray, faces: np.ndarray, parts: dict | None = None):
        from baker.geometry.normals import vertex_normals

        self.positions = np.ascontiguousarray(positions, np.float64)
        self.faces = np.ascontiguousarray(faces, np.int64)
        self.normals = vertex_normals(self.positions, self.faces)
        digest = hashlib.sha256()
        digest.update(np.ascontiguousarray(self.positions, "<f8").tobytes())
        digest.update(np.ascontiguousarray(self.faces, "<i8").tobytes())
        self.key = digest.hexdigest()
        self.parts = parts or {}
        self._scene = None
        self._part_scenes = {}

    @classmethod
    def from_asset(cls, asset) -> "SourceMesh":
        positions, faces, base, parts, first = [], [], 0, {}, 0
        for m in range(len(asset.meshes())):
            prims = asset.triangle_primitives(m)
            if not prims:
                continue
            welded = asset.welded(m, prims)
            positions.append(welded.positions)
            faces.append(welded.faces + base)
            base += len(welded.positions)
            name = part_name(asset.meshes()[m].get("name"), "_high")
            if name is not None:
                parts.setdefault(name, []).append(np.arange(first, first + len(welded.faces)))
            first += len(welded.faces)
        if not faces or not sum(len(f) for f in faces):
            raise BakerError(asset.source, "the --from source has no triangles")
        parts = {name: np.concatenate(ranges) for name, ranges in parts.items()} if len(parts) > 1 else {}
        return cls(np.concatenate(positions), np.concatenate(faces), parts)

    def part_scene(self, name: str):
        """(scene of the part's triangles, their indices in the whole high)."""
        if name not in self._part_scenes:
            from baker.geometry.raycast import RayScene

            triangles = self.parts[name]
            self._part_scenes[name] = (RayScene(self.positions, self.faces[triangles], quality="medium", robust=True),
                                       triangles)
        return self._part_scenes[name]

    @property
    def scene(self):
        if self._scene is None:
            from baker.geometry.raycast import RayScene

            # about one ray per texel, a few per triangle: the medium build (a 300k-triangle sculpt: 0.16 s of CPU
            # against 0.73 s for the high build's spatial splits, the same 1.1 s for 1M rays); robust: a ray from a
            # cage vertex straight through a vertex of the sculpt (the poles of the test spheres) does not miss
            self._scene = RayScene(self.positions, self.faces, quality="medium", robust=True)
        return self._scene

    def per_vertex(self, name: str, options_key: str, compute) -> np.ndarray:
        """``compute(self)`` -> (vertices, ...) values of a per-vertex bake of the high, once per (high mesh
        content, bake, options) in this process: a recipe baking several low meshes from one sculpt traces it once."""
        key = (self.key, name, options_key)
        if key not in PER_VERTEX_CACHE:
            values = np.asarray(compute(self))
            values.setflags(write=False)
            PER_VERTEX_CACHE[key] = values
            while len(PER_VERTEX_CACHE) > PER_VERTEX_CACHE_SIZE:
                PER_VERTEX_CACHE.popitem(last=False)
        PER_VERTEX_CACHE.move_to_end(key)
        return PER_VERTEX_CACHE[key]


PER_VERTEX_CACHE: OrderedDict = OrderedDict()
PER_VERTEX_CACHE_SIZE = 16


@dataclass
class SourceHits:
    """Where each sample's ray met the high mesh: ``triangle`` and ``bary`` (3 weights) on the high, the point and
    the interpolated unit smooth normal; ``hit`` False where the ray met nothing (those copy a neighbour's hit)."""

    source: SourceMesh
    triangle: np.ndarray  # (n,) int64
    bary: np.ndarray  # (n, 3)
    points: np.ndarray  # (n, 3)
    normals: np.ndarray  # (n, 3)
    hit: np.ndarray  # (n,) bool

    @property
    def misses(self) -> int:
        return int((~self.hit).sum())

    def interpolate(self, per_vertex: np.ndarray) -> np.ndarray:
        """Per-sample values of per-vertex values of the high."""
        from baker.texels.texture_space import interpolate

        return interpolate(per_vertex, self.source.faces, self.triangle, self.bary)


def record(request: TransferRequest, bake: str, kind: str, hit: np.ndarray) -> None:
    """Count a bake's samples (``kind``: texels, vertices; ``hit`` per sample) and misses for the summary and
    ``asset.extras.baker``; refuse a source that most rays miss."""
    samples, misses = len(hit), int((~hit).sum())
    request.summary.setdefault("bakes", {}).setdefault(bake, {})[kind] = {"samples": samples, "misses": misses}
    if samples and misses > (1.0 - OVERLAP_FRACTION) * samples:
        raise BakerError(request.source_path, f"the source does not overlap the low mesh: {misses} of {samples} "
                         f"{kind}' rays through the cage found no source surface (bake from the high mesh of the same "
                         "object; or a larger --cage-distance)")


def read_request(source_path, source_asset, cage_path=None, cage_asset=None, cage_distance=None) -> TransferRequest:
    """The request from the assets read: the high as a :class:`SourceMesh`, the cage's positions per primitive."""
    source = SourceMesh.from_asset(source_asset)
    cage = None
    if cage_asset is not None:
        cage = {}
        for m in range(len(cage_asset.meshes())):
            for p in cage_asset.triangle_primitives(m):
                g = cage_asset.primitive(m, p)
                cage[(m, p)] = (np.asarray(g.positions), np.asarray(g.faces))
    return TransferRequest(Path(source_path), source, None if cage_path is None else Path(cage_path), cage,
                           cage_distance)


def check_cage_topology(request: TransferRequest, low_asset) -> None:
    """The cage must hold the low's meshes and primitives with the same vertex counts and triangles."""
    if request.cage is None:
        return
    for m in range(len(low_asset.meshes())):
        for p in low_asset.triangle_primitives(m):
            g = low_asset.primitive(m, p)
            found = request.cage.get((m, p))
            if found is None:
                raise BakerError(request.cage_path, f"the cage has no mesh {m} primitive {p} (the low mesh has): a "
                                 "cage must have the low mesh's topology")
            positions, faces = found
            if len(positions) != len(g.positions) or faces.shape != g.faces.shape or not np.array_equal(faces, g.faces):
                raise BakerError(request.cage_path, f"mesh {m} primitive {p}: the cage's topology differs from the "
                                 f"low mesh's ({len(positions)} vertices, {len(faces)} triangles against "
                                 f"{len(g.positions)}, {len(g.faces)})")


def welded_smooth_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted normals over position-welded vertices: the same normal on both sides of a hard edge or a
    seam, so a cage pushed out along them has no gaps."""
    from baker.geometry.normals import vertex_normals
    from baker.geometry.welding import weld

    welded, inverse = weld(positions)
    return vertex_normals(welded, inverse[faces])[inverse]


def cage_positions(request: TransferRequest, geometry, source_vertex, distance: float) -> np.ndarray:
    """(vertices, 3) cage positions of a low primitive as the texels see it (after an unwrap split its vertices,
    ``source_vertex`` maps them to the primitive's vertices before)."""
    if request.cage is not None:
        positions = request.cage[(geometry.mesh, geometry.primitive)][0]
        if source_vertex is not None:
            return positions[source_vertex]
        return positions
    return geometry.positions + distance * welded_smooth_normals(geometry.positions, geometry.faces)


def trace(scene, origins: np.ndarray, directions: np.ndarray):
    """First hits of rays in chunks on every core (the compiled loop releases the GIL): (distance, triangle, u, v)."""
    from concurrent.futures import ThreadPoolExecutor

    n = len(origins)
    if n <= TRACE_CHUNK:
        return scene.first_hits(origins, directions)
    distance, face = np.empty(n, np.float32), np.empty(n, np.int64)
    u, v = np.empty(n, np.float32), np.empty(n, np.float32)

    def one(start):
        stop = min(start + TRACE_CHUNK, n)
        distance[start:stop], face[start:stop], u[start:stop], v[start:stop] = \
            scene.first_hits(origins[start:stop], directions[start:stop])

    threads = int(os.environ.get("BAKER_THREADS", 0) or 0) or os.cpu_count() or 1
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(one, range(0, n, TRACE_CHUNK)))
    return distance, face, u, v


def automatic_cage_distance(request: TransferRequest, low_asset) -> float:
    """The cage distance from the two meshes (see the module docstring); refuses a source that does not overlap."""
    from baker.geometry.normals import vertex_normals

    points, normals = [], []
    for m in range(len(low_asset.meshes())):
        prims = low_asset.triangle_primitives(m)
        if not prims:
            continue
        welded = low_asset.welded(m, prims)
        n = vertex_normals(welded.positions, welded.faces)
        corners = welded.positions[welded.faces]
        face_normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        length = np.linalg.norm(face_normals, axis=1)
        keep = length > 0
        points += [welded.positions, corners[keep].mean(axis=1)]
        normals += [n, face_normals[keep] / length[keep, None]]
    points, normals = np.concatenate(points), np.concatenate(normals)
    low_diag = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) or 1.0
    high = request.source.positions
    if np.any(high.min(axis=0) > points.max(axis=0)) or np.any(high.max(axis=0) < points.min(axis=0)):
        raise BakerError(request.source_path, "the source does not overlap the low mesh (their bounding boxes are "
                         "apart): bake from the high mesh of the same object, in the same place")
    scene = request.source.scene
    outward = trace(scene, points, normals)[0].astype(np.float64)
    inward = trace(scene, points, -normals)[0].astype(np.float64)
    distance = np.minimum(outward, inward)
    # a ray through a hole of the high (an open scan, a cut) crosses the whole shape: a sculpt lies within
    # MAX_OFFSET of the low's diagonal from it, and farther hits are not its offset
    found = distance <= MAX_OFFSET * low_diag
    if found.mean() < OVERLAP_FRACTION:
        raise BakerError(request.source_path, "the source does not overlap the low mesh (its surface is not near "
                         "the low's along the low's normals): bake from the high mesh of the same object")
    distance = distance[found]
    return float(CAGE_MARGIN * np.quantile(distance, CAGE_QUANTILE) + CAGE_FLOOR * low_diag)


def cage_distance(request: TransferRequest, low_asset) -> float:
    """The cage distance asked for, or the automatic one (computed once per request)."""
    if request.cage_distance is None:
        request.cage_distance = automatic_cage_distance(request, low_asset)
        request.summary["cageDistance"] = request.cage_distance
        request.summary["cageDistanceAutomatic"] = True
    return request.cage_distance


def low_parts(request: TransferRequest, low_asset) -> np.ndarray:
    """Per mesh of the low asset, the index into ``sorted(request.source.parts)`` of the high part it bakes from
    (its name less ``_low`` is a part's name less ``_high``), or -1: the whole high."""
    names = sorted(request.source.parts)
    out = np.full(len(low_asset.meshes()), -1, np.int64)
    for m, mesh in enumerate(low_asset.meshes()):
        name = part_name(mesh.get("name"), "_low")
        if name in request.source.parts:
            out[m] = names.index(name)
    if (out >= 0).any():
        request.summary["parts"] = sorted({names[k] for k in out if k >= 0})
    return out


def project(request: TransferRequest, low_points: np.ndarray, cage_points: np.ndarray,
            neighbours=None, parts: np.ndarray | None = None) -> SourceHits:
    """Rays from ``cage_points`` through ``low_points`` (as far again behind them) onto the high: the first hit.
    ``neighbours(hit) -> index``: for each sample the sample whose hit a miss copies (None: misses keep triangle 0).
    ``parts``: per sample the high part (:func:`low_parts`) its ray may hit, -1 for any."""
    source = request.source
    direction = low_points - cage_points
    length = np.linalg.norm(direction, axis=1)
    # a cage point on the low surface (cage distance 0, or a cage touching the low): the ray leaves along the normal
    unit = direction / np.maximum(length, 1e-30)[:, None]
    if parts is None or not (parts >= 0).any():
        distance, triangle, u, v = trace(source.scene, cage_points, unit)
    else:
        n = len(cage_points)
        distance, triangle = np.empty(n, np.float32), np.empty(n, np.int64)
        u, v = np.empty(n, np.float32), np.empty(n, np.float32)
        names = sorted(source.parts)
        for part in np.unique(parts):
            rows = np.flatnonzero(parts == part)
            if part < 0:
                scene, triangles = source.scene, None
            else:
                scene, triangles = source.part_scene(names[part])
            d, t, pu, pv = trace(scene, cage_points[rows], unit[rows])
            if triangles is not None:
                t = np.where(t >= 0, triangles[np.maximum(t, 0)], -1)
            distance[rows], triangle[rows], u[rows], v[rows] = d, t, pu, pv
    hit = (triangle >= 0) & (distance.astype(np.float64) <= 2.0 * length * (1.0 + 1e-6) + 1e-12)
    if neighbours is not None and hit.any() and not hit.all():
        take = neighbours(hit)
    else:
        take = np.arange(len(hit))
    triangle = np.where(hit, triangle, 0)[take]
    u, v = np.where(hit, u, 0.0)[take].astype(np.float64), np.where(hit, v, 0.0)[take].astype(np.float64)
    bary = np.stack([1.0 - u - v, u, v], axis=1)
    from baker.texels.texture_space import interpolate

    points = interpolate(source.positions, source.faces, triangle, bary)
    normals = interpolate(source.normals, source.faces, triangle, bary)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
    return SourceHits(source, triangle, bary, points, normals, hit)


def project_welded(request: TransferRequest, asset, welded, normals: np.ndarray) -> SourceHits:
    """The high's surface for each vertex of a welded low mesh (:class:`~baker.geometry.asset.WeldedMesh`, with its
    smooth ``normals``): per-vertex bakes of the low take the high's values there. The cage is the cage file's
    vertices, or the vertices pushed out by the cage distance; a miss takes the nearest vertex's hit."""
    if request.cage is not None:
        cage = np.empty_like(welded.positions)
        for i, g in enumerate(welded.geometries):
            cage[welded.inverse[welded.offsets[i]: welded.offsets[i + 1]]] = request.cage[(g.mesh, g.primitive)][0]
    else:
        cage = welded.positions + cage_distance(request, asset) * normals

    def nearest_hit(hit):
        from scipy.spatial import cKDTree  # imported here: scipy is a large share of start-up

        found = np.flatnonzero(hit)
        _, nearest = cKDTree(welded.positions[found]).query(welded.positions)
        return np.where(hit, np.arange(len(hit)), found[nearest])

    part = low_parts(request, asset)[welded.geometries[0].mesh]
    return project(request, np.asarray(welded.positions), cage, nearest_hit,
                   np.full(len(welded.positions), part, np.int64))
