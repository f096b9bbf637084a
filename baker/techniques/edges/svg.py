"""The parts of ``baker lines IN -o drawing.svg`` (run by :func:`baker.techniques.edges.step.run_lines`): a
hidden-line drawing of an asset from a camera (RTR4 15.2.4-15.2.5).

The scene's triangles (every node's mesh, in world space) are welded and classified (:mod:`baker.geometry.edges`), the
contour edges for the camera are found by eq. 15.1 and chained with the crease, boundary and material edges,
visibility comes from rays cast with Embree (:mod:`baker.techniques.edges.line_drawing`), and the polylines are written as SVG:
visible lines solid, hidden ones dashed (``--hidden``), stroke widths by type.
"""
from __future__ import annotations

import math

import numpy as np

from baker.techniques.edges import line_drawing as L
from baker.errors import BakerError
from baker.gltf.document import world_nodes

DEFAULT_WIDTHS = {"contour": 2.0, "boundary": 1.5, "crease": 1.0, "material": 1.0}




def parse_vector(text: str, what: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in text.split(",")], np.float64)
    except ValueError:
        raise BakerError(None, f"{what} must be three comma-separated numbers, got {text!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise BakerError(None, f"{what} must be three comma-separated numbers, got {text!r}")
    return v


# ----------------------------------------------------------------------------------------------------------- scene
def scene_triangles(asset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World-space (positions, faces, face group) of every mesh instance of the default scene."""
    gltf = asset.doc.json
    instances = [(n["mesh"], w) for i, w in world_nodes(gltf) if "mesh" in (n := gltf["nodes"][i])]
    if not instances:
        instances = [(m, np.eye(4)) for m in range(len(asset.meshes()))]
    positions, faces, groups, base, group = [], [], [], 0, 0
    for mesh, world in instances:
        for p in asset.triangle_primitives(mesh):
            g = asset.primitive(mesh, p)
            if not len(g.faces):
                continue
            pts = g.positions @ world[:3, :3].T + world[:3, 3]
            f = g.faces if np.linalg.det(world[:3, :3]) >= 0 else g.faces[:, ::-1]  # mirrored: keep front faces
            positions.append(pts)
            faces.append(f + base)
            groups.append(np.full(len(f), group))
            base += len(pts)
            group += 1
    if not positions:
        raise BakerError(asset.source, "no triangles in the default scene")
    return np.concatenate(positions), np.concatenate(faces), np.concatenate(groups)


def gltf_camera(gltf: dict, name: str):
    """(world matrix, camera dict) of the camera named ``name`` (camera name or node name), or None."""
    cameras = gltf.get("cameras") or []
    for i, world in world_nodes(gltf):
        node = gltf["nodes"][i]
        if "camera" in node:
            cam = cameras[node["camera"]]
            if name in (cam.get("name"), node.get("name")):
                return world, cam
    return None


def make_camera(args, asset, positions: np.ndarray) -> L.Camera:
    size = None
    if args.size:
        try:
            w, h = (int(x) for x in args.size.lower().split("x"))
            assert w > 0 and h > 0
        except (ValueError, AssertionError):
            raise BakerError(None, f"--size must be WIDTHxHEIGHT, got {args.size!r}") from None
        size = (w, h)
    up = parse_vector(args.up, "--up")
    center = (positions.min(0) + positions.max(0)) / 2.0
    camera_spec = args.camera
    if camera_spec and not all(c in "0123456789.,-+eE " for c in camera_spec):
        found = gltf_camera(asset.doc.json, camera_spec)
        if found is None:
            raise BakerError(asset.source, f"no camera named {camera_spec!r}")
        world, cam = found
        eye = world[:3, 3]
        forward = -world[:3, 2] / np.linalg.norm(world[:3, 2])
        cam_up = world[:3, 1] / np.linalg.norm(world[:3, 1])
        if cam.get("type") == "orthographic":
            o = cam.get("orthographic", {})
            aspect = float(o.get("xmag", 1.0)) / float(o.get("ymag", 1.0))
            w, h = size or (int(round(800 * aspect)), 800)
            return L.Camera(eye, eye + forward, cam_up, w, h, yfov=None, ymag=float(o.get("ymag", 1.0)))
        persp = cam.get("perspective", {})
        aspect = persp.get("aspectRatio") or 1.0
        w, h = size or (int(round(800 * aspect)), 800)
        yfov = math.radians(args.fov) if args.fov else float(persp.get("yfov", math.radians(40.0)))
        return L.Camera(eye, eye + forward, cam_up, w, h, yfov, znear=float(persp.get("znear", 1e-3)))
    w, h = size or (800, 800)
    target = parse_vector(args.target, "--target") if args.target else center
    fov = args.fov or 40.0
    if camera_spec:
        eye = parse_vector(camera_spec, "--camera")
    else:
        eye = L.fit_camera(positions, w, h, fov).eye + (target - center)
    if np.linalg.norm(eye - target) < 1e-12:
        raise BakerError(None, "the camera position equals the target")
    if args.orthographic:
        return L.Camera(eye, target, up, w, h, yfov=None, ymag=float(args.orthographic))
    return L.Camera(eye, target, up, w, h, math.radians(fov))


# ----------------------------------------------------------------------------------------------------------- SVG
def _path(points: np.ndarray, closed: bool) -> str:
    coords = [f"{x:.2f} {y:.2f}" for x, y in points.tolist()]
    return "M" + " L".join(coords) + (" Z" if closed else "")


def svg_document(lines: list, width: int, height: int, widths: dict, hidden: bool, hatching=None,
                 hatch_width: float = 0.6) -> str:
    """SVG text: one group per (type, visibility), visible lines solid black, hidden lines dashed grey; with
    ``hatching`` (a :class:`baker.techniques.edges.hatching.Hatching`) its strokes first, underneath, in the groups
    ``hatching primary`` and ``hatching cross``."""
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}">',
           '<rect width="100%" height="100%" fill="white"/>']
    if hatching is not None:
        for name, strokes in (("primary", hatching.primary), ("cross", hatching.cross)):
            if not strokes:
                continue
            out.append(f'<g class="hatching {name}" fill="none" stroke="#000000" stroke-width="{hatch_width:g}" '
                       'stroke-linecap="round" stroke-linejoin="round">')
            out.extend(f'<path d="{_path(s, False)}"/>' for s in strokes)
            out.append("</g>")
    for visible in ((False, True) if hidden else (True,)):  # hidden first: visible strokes draw on top
        for kind, name in enumerate(L.TYPE_NAMES):
            paths = [l for l in lines if l.kind == kind and l.visible == visible]
            if not paths:
                continue
            w = widths[name] * (1.0 if visible else 0.6)
            style = (f'stroke="#000000" stroke-width="{w:g}"' if visible else
                     f'stroke="#808080" stroke-width="{w:g}" stroke-dasharray="{3 * w:g} {2 * w:g}"')
            out.append(f'<g class="{name} {"visible" if visible else "hidden"}" fill="none" {style} '
                       'stroke-linecap="round" stroke-linejoin="round">')
            out.extend(f'<path d="{_path(l.points, l.closed)}"/>' for l in paths)
            out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"
