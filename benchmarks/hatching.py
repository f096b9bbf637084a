"""Hatching directions (issue 38 item 5): how well the lapped stroke parameterization's u axis follows the principal
directions, what it costs in distortion, against the mesh's own UVs, xatlas's UVs and libigl's principal directions.

    python benchmarks/hatching.py [--meshes torus,bunny,spot] [--repeats 8] [--markdown]

Meshes: a torus R = 1, r = 0.35 (120 x 48 grid; analytic principal directions: around the tube and along the
ring), the Stanford bunny (no UVs of its own) and Spot (held back from the tests; its own UVs), both from
../shared/assets/meshes (skipped when absent). Every mesh is welded by exact position first.

Rows per mesh:
- ``baker field``: the cross field of ``baker.geometry.direction_field`` (Knöppel et al. 2013) aligned with
  ``principal_curvatures``' smoothed principal directions (per vertex; time includes the curvature);
- ``baker lapped``: ``stroke_parameterization`` (Praun et al. 2000) on that field, ``--repeats`` texture repeats
  across the bounding-box diagonal; the stroke direction is its u axis on each face;
- ``own UVs`` (where the mesh has them) and ``xatlas`` (baker's unwrap, ``baker.texels.texture_space.unwrap``):
  their u axis on each face;
- ``libigl PD1`` (peer, ``pip install libigl``, the ``benchmark`` extra): ``igl.principal_curvature``'s maximal
  direction per vertex (quadric fit, Panozzo et al. 2010; radius 5, no smoothing, no field).

Columns:
- angle: RMS, in degrees, of the angle between the stroke direction and the nearest principal direction (modulo 90:
  a cross), projected into the face's plane, where |k1 - k2| is large: faces (vertices for per-vertex rows) whose
  |k1 - k2| from ``principal_curvatures`` is at least its median over the mesh (the more anisotropic half). The
  reference is the analytic direction on the torus and the smoothed principal field (``principal_curvatures``,
  2 passes of tensor smoothing) on the others, so on those the baker rows are measured against the field they were
  built from and libigl against a field it did not use: read the torus for a fair comparison;
- area p95/p5: the 95th over the 5th percentile of texels per surface area (UV area / 3D area) per face;
- conformal median / p95: sigma_max / sigma_min of each face's surface-to-UV Jacobian (1: angles kept);
- flipped / degenerate: faces whose UV area has the sign opposite to most of their chart's (a chart mirrored as a
  whole is no defect) / is below 1e-12 of the largest;
- charts and faces per chart: connected pieces of the UV mesh (patches for baker);
- seconds: wall time of that row's computation (one run, numba compiled; the machine is shared, read ratios);
  the lapped row's includes the field's.
"""
from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from baker.geometry.normals import vertex_normals  # noqa: E402
from baker.techniques.curvature.kernel import principal_curvatures  # noqa: E402
from baker.geometry.direction_field import anisotropy, cross_field  # noqa: E402
from baker.techniques.tam.stroke_parameterization import stroke_parameterization  # noqa: E402
from baker.texels.texture_space import unwrap  # noqa: E402

ASSETS = ROOT.parent / "shared" / "assets" / "meshes"
if not ASSETS.exists():
    ASSETS = Path("/work/shared/assets/meshes")


def torus(R=1.0, r=0.35, nu=120, nv=48):
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False), np.linspace(0, 2 * np.pi, nv, endpoint=False),
                       indexing="ij")
    u, v = u.reshape(-1), v.reshape(-1)
    positions = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1)
    idx = np.arange(nu * nv).reshape(nu, nv)
    a, b, c = idx, np.roll(idx, -1, 0), np.roll(idx, -1, 1)
    d = np.roll(b, -1, 1)
    faces = np.concatenate([np.stack([a, d, b], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return positions, faces


def torus_reference(points, R=1.0):
    """The analytic direction around the tube (k1) at torus points (the other is the normal cross it)."""
    ring = np.stack([-points[:, 1], points[:, 0], np.zeros(len(points))], 1)
    ring /= np.linalg.norm(ring, axis=1)[:, None]
    centre = np.stack([points[:, 0], points[:, 1], np.zeros(len(points))], 1)
    centre *= R / np.linalg.norm(centre, axis=1)[:, None]
    normal = points - centre
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return np.cross(normal, ring)


def load(name: str):
    """(welded positions, faces, per-corner own UVs or None)."""
    if name == "torus":
        positions, faces = torus()
        return positions, faces, None
    path = ASSETS / {"bunny": "stanford-bunny.obj"}.get(name, f"{name}.obj")
    if not path.exists():
        return None
    positions, texcoords, faces, uv_faces = read_obj(path)
    # weld by exact position, keeping only the vertices faces use (a vertex of no face is a zero row of the field's
    # matrix)
    positions, inverse = np.unique(positions, axis=0, return_inverse=True)
    faces = inverse.reshape(-1)[faces]
    used, faces = np.unique(faces, return_inverse=True)
    positions, faces = positions[used], faces.reshape(-1, 3)
    return positions, faces, (texcoords[uv_faces], uv_faces) if uv_faces is not None else None


def read_obj(path: Path):
    """(positions, texcoords, faces, faces on the texcoords or None) of a triangle or polygon OBJ (polygons as
    fans): the UV faces kept apart from the position faces, which a reader splitting vertices per (v, vt) pair would
    not show as charts."""
    positions, texcoords, faces, uv_faces = [], [], [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                positions.append([float(x) for x in parts[1:4]])
            elif parts[0] == "vt":
                texcoords.append([float(x) for x in parts[1:3]])
            elif parts[0] == "f":
                corners = [c.split("/") for c in parts[1:]]
                v = [int(c[0]) - 1 if int(c[0]) > 0 else len(positions) + int(c[0]) for c in corners]
                t = [int(c[1]) - 1 if len(c) > 1 and c[1] else -1 for c in corners]
                for k in range(1, len(v) - 1):
                    faces.append([v[0], v[k], v[k + 1]])
                    uv_faces.append([t[0], t[k], t[k + 1]])
    uv_faces = np.asarray(uv_faces, np.int64)
    has_uv = len(texcoords) and (uv_faces >= 0).all()
    return (np.asarray(positions, np.float64), np.asarray(texcoords, np.float64), np.asarray(faces, np.int64),
            uv_faces if has_uv else None)


def cross_angle(a, b, normal):
    """Degrees between tangents a and b (both projected into the plane of ``normal``), modulo 90."""
    a = a - normal * np.einsum("ij,ij->i", a, normal)[:, None]
    b = b - normal * np.einsum("ij,ij->i", b, normal)[:, None]
    cos = np.abs(np.einsum("ij,ij->i", a, b)) / np.maximum(
        np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
    angle = np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))
    return np.minimum(angle, 90.0 - angle)


def chart_measures(positions, faces, corner_uv):
    """Per face: signed UV area / 3D area (texel density), conformal distortion, the u axis on the surface."""
    p = positions[faces]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    normal = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(normal, axis=1)
    normal /= np.maximum(2 * area, 1e-300)[:, None]
    t1 = e1 / np.maximum(np.linalg.norm(e1, axis=1), 1e-300)[:, None]
    t2 = np.cross(normal, t1)
    x = np.stack([np.stack([np.einsum("ij,ij->i", e, t1), np.einsum("ij,ij->i", e, t2)], 1) for e in (e1, e2)], 2)
    d = np.stack([corner_uv[:, 1] - corner_uv[:, 0], corner_uv[:, 2] - corner_uv[:, 0]], 2)  # (f, 2 uv, 2 edges)
    with np.errstate(divide="ignore", invalid="ignore"):
        jacobian = d @ np.linalg.inv(x)  # local surface coordinates -> uv
        signed = 0.5 * (d[:, 0, 0] * d[:, 1, 1] - d[:, 0, 1] * d[:, 1, 0])
        sigma = np.linalg.svd(jacobian, compute_uv=False)
        conformal = sigma[:, 0] / sigma[:, 1]
        # the u axis: the surface direction along which v stays constant, J^-1 (1, 0)
        local = np.stack([jacobian[:, 1, 1], -jacobian[:, 1, 0]], 1)
        axis = local[:, :1] * t1 + local[:, 1:] * t2
    return signed / np.maximum(area, 1e-300), conformal, axis, normal


def chart_labels(faces_on_uv_vertices):
    """The chart of each face: connected pieces of the mesh on its UV vertices."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    f = np.asarray(faces_on_uv_vertices)
    n = int(f.max()) + 1
    rows, cols = f[:, [0, 1, 2]].reshape(-1), f[:, [1, 2, 0]].reshape(-1)
    count, label = connected_components(sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)),
                                        directed=False)
    return label[f[:, 0]]


def uv_row(name, positions, faces, corner_uv, chart, reference, selected, seconds):
    density, conformal, axis, normal = chart_measures(positions, faces, corner_uv)
    angle = np.concatenate([cross_angle(axis[selected], reference[k][selected], normal[selected])
                            for k in range(len(reference))])
    tiny = np.abs(density) <= 1e-12 * np.abs(density).max()
    # a chart mirrored as a whole is no defect (strokes drawn mirrored are strokes): a face is flipped when its
    # orientation differs from most of its chart's
    _, chart = np.unique(chart, return_inverse=True)
    positive = np.bincount(chart, weights=(density > 0).astype(float))
    majority = np.where(positive >= np.bincount(chart) / 2, 1.0, -1.0)[chart]
    flipped = np.count_nonzero((density * majority < 0) & ~tiny)
    chart_sizes = np.bincount(chart)
    size = np.abs(density[~tiny])
    return {"row": name, "angle": float(np.sqrt(np.nanmean(angle ** 2))),
            "area": float(np.percentile(size, 95) / np.percentile(size, 5)),
            "conformal": (float(np.nanmedian(conformal)), float(np.nanpercentile(conformal, 95))),
            "flipped": (int(flipped), int(np.count_nonzero(tiny))), "charts": len(chart_sizes),
            "per_chart": (float(np.mean(chart_sizes)), float(np.median(chart_sizes))), "seconds": seconds}


def measure(mesh: str, repeats: float) -> list[dict]:
    loaded = load(mesh)
    if loaded is None:
        print(f"{mesh}: not found under {ASSETS}, skipped", file=sys.stderr)
        return []
    positions, faces, own_uv = loaded
    rows = []
    start = time.perf_counter()
    curvature = principal_curvatures(positions, faces)
    normals = vertex_normals(positions, faces)
    field = cross_field(positions, faces, normals, directions=curvature.direction1,
                        strength=anisotropy(curvature.k1, curvature.k2))
    field_seconds = time.perf_counter() - start

    spread = np.abs(curvature.k1 - curvature.k2)
    vertex_selected = spread >= np.median(spread)
    face_selected = spread[faces].mean(axis=1) >= np.median(spread)
    if mesh == "torus":
        vertex_reference = torus_reference(positions)
        centroid = positions[faces].mean(axis=1)
        face_reference = [torus_reference(centroid)]
    else:
        vertex_reference = curvature.direction1
        face_reference = [curvature.direction1[faces[:, k]] for k in range(3)]  # each corner's, in the face plane

    angle = cross_angle(field.direction[vertex_selected], vertex_reference[vertex_selected], normals[vertex_selected])
    rows.append({"row": "baker field (per vertex)", "angle": float(np.sqrt(np.mean(angle ** 2))),
                 "seconds": field_seconds, "singularities": len(field.singular_faces)})

    diagonal = float(np.linalg.norm(positions.max(0) - positions.min(0)))
    start = time.perf_counter()
    lapped = stroke_parameterization(positions, faces, normals, field.direction, scale=repeats / diagonal)
    lapped_seconds = time.perf_counter() - start
    row = uv_row("baker lapped (u axis; seconds: field + lapped)", positions, faces, lapped.uv[lapped.faces], lapped.patch,
                 face_reference, face_selected, lapped_seconds + field_seconds)
    row["fallback"] = lapped.fallback_count
    rows.append(row)

    if own_uv is not None:
        corner_uv, uv_faces = own_uv
        rows.append(uv_row("own UVs", positions, faces, corner_uv, chart_labels(uv_faces), face_reference,
                           face_selected, 0.0))

    start = time.perf_counter()
    (vmapping, xfaces, xuv), = unwrap([(positions, faces)], 2048)
    xatlas_seconds = time.perf_counter() - start
    # xatlas keeps the faces in order: corner k of face f is xfaces[f, k], a copy of faces[f, k]
    assert np.array_equal(vmapping[xfaces], faces)
    rows.append(uv_row("xatlas", positions, faces, xuv[xfaces], chart_labels(xfaces), face_reference, face_selected,
                       xatlas_seconds))

    try:
        import igl
    except ImportError:
        print("libigl not installed (pip install libigl): no peer row", file=sys.stderr)
    else:
        start = time.perf_counter()
        pd1, _, _, _, _ = igl.principal_curvature(np.ascontiguousarray(positions), np.ascontiguousarray(faces))
        igl_seconds = time.perf_counter() - start
        angle = cross_angle(pd1[vertex_selected], vertex_reference[vertex_selected], normals[vertex_selected])
        rows.append({"row": "libigl PD1 (peer, per vertex)", "angle": float(np.sqrt(np.nanmean(angle ** 2))),
                     "seconds": igl_seconds})
    for r in rows:
        r["mesh"] = f"{mesh} ({len(faces):,} faces)"
    return rows


def markdown(rows: list[dict]) -> str:
    out = ["| mesh | stroke direction | angle RMS (deg) | area p95/p5 | conformal median / p95 | flipped / degenerate "
           "| charts (faces per chart mean / median) | seconds |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        extra = f" ({r['singularities']} singular faces)" if "singularities" in r else ""
        extra += f" ({r['fallback']} fallback)" if r.get("fallback") else ""
        area = f"{r['area']:.2f}" if "area" in r else "-"
        conformal = f"{r['conformal'][0]:.3f} / {r['conformal'][1]:.3f}" if "conformal" in r else "-"
        flipped = f"{r['flipped'][0]} / {r['flipped'][1]}" if "flipped" in r else "-"
        charts = (f"{r['charts']:,} ({r['per_chart'][0]:.0f} / {r['per_chart'][1]:.0f})" if "charts" in r else "-")
        out.append(f"| {r['mesh']} | {r['row']}{extra} | {r['angle']:.2f} | {area} | {conformal} | {flipped} | "
                   f"{charts} | {r['seconds']:.2f} |")
    return "\n".join(out)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", default="torus,bunny,spot")
    parser.add_argument("--repeats", type=float, default=8.0,
                        help="stroke texture repeats across the bounding-box diagonal (default 8)")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    # compile / load every numba kernel first (a small torus through every row), so the first mesh's seconds are
    # not the imports'
    positions, faces = torus(nu=24, nv=12)
    curvature = principal_curvatures(positions, faces)
    normals = vertex_normals(positions, faces)
    warm = cross_field(positions, faces, normals, directions=curvature.direction1)
    stroke_parameterization(positions, faces, normals, warm.direction)
    unwrap([(positions, faces)], 256)
    rows = []
    for mesh in args.meshes.split(","):
        rows.extend(measure(mesh.strip(), args.repeats))
    load_average = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{datetime.date.today()} {platform.machine()} {os.cpu_count()} cores, load {load_average:.1f}")
    if args.markdown:
        print(markdown(rows))
    else:
        for r in rows:
            print(r)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
