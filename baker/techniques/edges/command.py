"""``baker lines IN -o drawing.svg``: the parser; the work is :func:`baker.techniques.edges.step.run_lines`, imported
when it runs."""
from __future__ import annotations

from baker import memory
from baker.technique import lazy


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("lines", help="draw contour, crease and boundary lines of an asset as SVG")
    p.add_argument("input", help="input asset (.gltf .glb .obj .ply .stl .usd .usda .usdc .usdz)")
    p.add_argument("-o", "--output", required=True, help="output .svg")
    p.add_argument("--camera", help="a glTF camera (camera or node name), or the eye position X,Y,Z "
                                    "(default: in front of the scene, along -Z)")
    p.add_argument("--target", help="point looked at, X,Y,Z (default: the scene's bounding-box centre)")
    p.add_argument("--up", default="0,1,0", help="up vector X,Y,Z (default: 0,1,0)")
    p.add_argument("--fov", type=float, help="vertical field of view in degrees (default 40, or the glTF camera's)")
    p.add_argument("--orthographic", type=float, metavar="HALF_HEIGHT",
                   help="orthographic view of this half-height in scene units instead of a perspective one")
    p.add_argument("--size", help="WIDTHxHEIGHT in pixels (default 800x800, or the glTF camera's aspect ratio)")
    p.add_argument("--hidden", action="store_true", help="also draw hidden lines, dashed")
    p.add_argument("--crease-angle", type=float, default=60.0, help="crease threshold in degrees (default 60)")
    p.add_argument("--no-creases", action="store_true", help="draw contours and boundaries only")
    p.add_argument("--widths", default=None, help="stroke widths in pixels, e.g. contour=2,boundary=1.5,crease=1,"
                                                  "material=1")
    p.add_argument("--step", type=float, default=2.0, help="visibility sampling step along lines, pixels (default 2)")
    p.add_argument("--hatching", action="store_true",
                   help="also draw hatching strokes along the surface's principal-direction cross field, evenly "
                        "spaced, denser where a Lambert light leaves it darker, cross-hatched where darkest")
    p.add_argument("--hatch-spacing", type=float, default=6.0,
                   help="hatching: stroke spacing in pixels at the darkest tone (default 6; up to 4x wider in light "
                        "tones)")
    p.add_argument("--hatch-width", type=float, default=0.6, help="hatching: stroke width in pixels (default 0.6)")
    p.add_argument("--light", help="hatching: world direction towards the light X,Y,Z (default: from the upper "
                                   "left of the view, in front of the subject)")
    p.add_argument("--seed", type=int, default=0, help="hatching: seed of the stroke placement (default 0)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    memory.add_argument(p)
    p.set_defaults(func=lazy("baker.techniques.edges.step:run_lines"))
