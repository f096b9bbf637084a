"""Glyph atlases against independent truth: exact nonzero rasterizations of the outlines, brute-force distances,
fontTools' own glyph bounds, the legacy kern table, and round trips through the written PNG/JSON/GLB files."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from baker.techniques.glyphs.options import GlyphOptions
from baker.techniques.glyphs.kernel import bake_atlas
from baker.techniques.glyphs.outline import load_font, parse_charset
from baker.techniques.glyphs.atlas import pack
from baker.techniques.glyphs.coloring import edge_colors
from baker.techniques.glyphs.outline import Font, FontMetrics, Glyph
from baker.techniques.glyphs.quality import atlas_errors, flatten, magnified_inside, nonzero_raster, reference_coverage
from baker.techniques.glyphs.sdf import true_distance_field
from baker.techniques.glyphs.shape import from_contours, prepare
from baker.cli import main
from baker.gltf.images import read_image
from baker.validate import validate_file
from conftest import assert_khronos_clean

FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
needs_font = pytest.mark.skipif(not FONT.is_file(), reason=f"{FONT} not found")


@pytest.fixture(scope="module")
def dejavu():
    if not FONT.is_file():
        pytest.skip(f"{FONT} not found")
    return load_font(FONT, "ascii")


@pytest.fixture(scope="module")
def scores(dejavu):
    """Quality of SDF and MSDF atlases of DejaVu Sans ASCII at 48 px/em, range 4 (the acceptance setting)."""
    out = {}
    for kind in ("sdf", "msdf"):
        atlas = bake_atlas(dejavu, GlyphOptions(type=kind, size=48, range=4))
        out[kind] = (atlas, {e.codepoint: e for e in atlas_errors(atlas, magnify=8, topology=kind == "msdf")})
    return out


# ---------------------------------------------------------------------------------------------------- acceptance
def test_msdf_quality_beats_sdf_and_no_glyph_above_one_percent(scores):
    sdf = np.array([e.error for e in scores["sdf"][1].values()])
    msdf = np.array([e.error for e in scores["msdf"][1].values()])
    assert len(msdf) == 94  # every printable ASCII character but the space
    assert msdf.mean() < sdf.mean(), (msdf.mean(), sdf.mean())
    worst = max(scores["msdf"][1].values(), key=lambda e: e.error)
    assert worst.error < 0.01, f"{chr(worst.codepoint)!r}: {worst.error:.2%}"


def test_sign_right_everywhere_no_holes_or_blobs(scores, dejavu):
    """Same ink components and holes as the exact outline for every glyph, and every wrongly covered pixel lies
    within one atlas texel of the true edge (so no hole or blob anywhere), including $ @ & g."""
    atlas, errors = scores["msdf"]
    for cp, e in errors.items():
        assert e.components[0] == e.components[1], f"{chr(cp)!r}: ink components {e.components}"
        assert e.holes[0] == e.holes[1], f"{chr(cp)!r}: holes {e.holes}"
    values = atlas.image / 255.0
    shapes = {g.codepoint: g.shape for g in dejavu.glyphs}
    for ch in "$@&g":
        g = next(x for x in atlas.glyphs if x.codepoint == ord(ch))
        inside = magnified_inside(values, g.atlas, 8)
        h, w = inside.shape[0] // 8, inside.shape[1] // 8
        truth = reference_coverage(shapes[ord(ch)], 48 / 2048, g.plane[0] * 48, g.plane[1] * 48, w, h)
        edge = truth ^ ndimage.binary_erosion(truth, border_value=0)
        far = ndimage.distance_transform_edt(~edge)
        wrong = inside != truth
        assert (far[wrong] <= 8).all(), f"{ch!r}: wrong pixel {far[wrong].max()} px away"


def test_quality_holds_at_another_magnification(dejavu, scores):
    """The error correction checks a 5 x 5 grid per cell; a 7x render (a different grid) must be as clean."""
    atlas = scores["msdf"][0]
    errors = atlas_errors(atlas, magnify=7)
    assert max(e.error for e in errors) < 0.01


def test_texel_centres_have_the_winding_sign(scores, dejavu):
    """At every texel centre the median is inside exactly when the outline's nonzero winding says so."""
    atlas = scores["msdf"][0]
    values = atlas.image / 255.0
    shapes = {g.codepoint: g.shape for g in dejavu.glyphs}
    for g in atlas.glyphs:
        if g.atlas is None:
            continue
        l, b, r, t = (int(v) for v in g.atlas)
        block = values[atlas.height - t: atlas.height - b, l:r][::-1]
        median = np.median(block[..., :3], axis=2)
        lines = flatten(shapes[g.codepoint]) * (48 / 2048) - np.array([g.plane[0], g.plane[1]]) * 48
        truth = nonzero_raster(lines, r - l, t - b)
        exact = true_distance_field(_pixel_shape(shapes[g.codepoint], g), r - l, t - b)
        decided = np.abs(exact) > 0.02  # 8-bit quantization decides texels closer than that
        assert ((median > 0.5) == truth)[decided].all(), chr(g.codepoint)


def _pixel_shape(shape, g):
    return prepare(shape).transformed(48 / 2048, -g.plane[0] * 48, -g.plane[1] * 48)


# ---------------------------------------------------------------------------------------------------- distances
def _brute_distance(shape, px, py):
    lines = flatten(shape, steps=4000)
    a, b = lines[:, 0], lines[:, 1]
    p = np.stack([px, py], -1).reshape(-1, 1, 2)
    ab = b - a
    t = np.clip(((p - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0, 1)
    d = np.linalg.norm(p - (a + t[..., None] * ab), axis=-1).min(axis=1)
    return d.reshape(np.shape(px))


def _circle_cubic(cx, cy, r, reverse=False):
    k = 0.5522847498 * r
    pts = [((cx + r, cy), (cx + r, cy + k), (cx + k, cy + r), (cx, cy + r)),
           ((cx, cy + r), (cx - k, cy + r), (cx - r, cy + k), (cx - r, cy)),
           ((cx - r, cy), (cx - r, cy - k), (cx - k, cy - r), (cx, cy - r)),
           ((cx, cy - r), (cx + k, cy - r), (cx + r, cy - k), (cx + r, cy))]
    contour = [(3, list(p)) for p in pts]
    if reverse:
        contour = [(3, list(p[::-1])) for p in pts[::-1]]
    return contour


def _square(x0, y0, x1, y1, clockwise=False):
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    if clockwise:
        corners = corners[::-1]
    return [(1, [corners[i], corners[(i + 1) % 4]]) for i in range(4)]


def _quad_blob():
    return [(2, [(4, 4), (16, 2), (20, 12)]), (2, [(20, 12), (22, 22), (8, 20)]), (1, [(8, 20), (4, 4)])]


@pytest.mark.parametrize("name", ["cubic circle", "quadratic blob", "overlapping and reversed"])
def test_true_distance_is_exact_with_nonzero_sign(name):
    contours = {
        "cubic circle": [_circle_cubic(12, 12, 7.3)],
        "quadratic blob": [_quad_blob()],
        # two overlapping squares drawn the same way, plus a circle drawn the other way that overlaps both:
        # nonzero fills the union of the squares and the disc where the windings do not cancel
        "overlapping and reversed": [_square(3, 3, 14, 14), _square(9, 8, 21, 20), _circle_cubic(15, 7, 4.2, True)],
    }[name]
    shape = from_contours(contours)
    w = h = 24
    field = true_distance_field(prepare(shape), w, h)
    jj, ii = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    inside = nonzero_raster(flatten(shape, steps=4000), w, h)
    # truth: the distance to the boundary of the filled region = to the flattened outline, except that edges with
    # the same fill on both sides (inside an overlap) are no boundary: check those regions by sign only
    brute = _brute_distance(shape, jj, ii)
    decided = brute > 1e-3
    assert ((field > 0) == inside)[decided].all()
    if name != "overlapping and reversed":
        np.testing.assert_allclose(np.abs(field), brute, atol=2e-3)
    else:
        # baker drops whole segments that bound nothing, but does not split segments where contours cross: a
        # segment partly inside an overlap still counts, so the distance may be shorter than the true boundary's
        lines = flatten(shape, steps=300)
        mid = lines.mean(axis=1)
        n = np.stack([-(lines[:, 1, 1] - lines[:, 0, 1]), lines[:, 1, 0] - lines[:, 0, 0]], 1)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        keep = np.array([_fill(lines, m + 1e-4 * k) != _fill(lines, m - 1e-4 * k) for m, k in zip(mid, n)])
        d = _brute_lines(lines[keep], jj, ii)
        assert (np.abs(field) <= d + 2e-3).all()
        assert np.mean(np.abs(np.abs(field) - d) < 2e-3) > 0.98


def _fill(lines, p):
    a, b = lines[:, 0], lines[:, 1]
    up = (a[:, 1] <= p[1]) & (p[1] < b[:, 1])
    down = (b[:, 1] <= p[1]) & (p[1] < a[:, 1])
    t = (p[1] - a[:, 1]) / np.where(a[:, 1] == b[:, 1], 1, b[:, 1] - a[:, 1])
    right = a[:, 0] + t * (b[:, 0] - a[:, 0]) > p[0]
    return int((up & right).sum() - (down & right).sum()) != 0


def _brute_lines(lines, px, py):
    a, b = lines[:, 0], lines[:, 1]
    p = np.stack([px, py], -1).reshape(-1, 1, 2)
    ab = b - a
    t = np.clip(((p - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0, 1)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1).min(axis=1).reshape(np.shape(px))


def test_overlapping_contours_render_without_artifacts():
    """Overlapping and reversed contours (as in variable fonts), scored like a font glyph: low error, and every wrong
    pixel within one texel of the true edge (no hole or blob away from it). Where contours cross, baker does not make
    the crossing a colored corner, so MSDF may show specks there: bounded here to the edge's texel."""
    shape = from_contours([_square(100, 100, 700, 700), _square(400, 300, 1000, 1100),
                           _circle_cubic(750, 350, 260, True), _circle_cubic(300, 800, 200)])
    font = Font("synthetic", "synthetic", FontMetrics(1000, 900, -200, 1200, -100, 50),
                [Glyph(65, "A", 1, 1100.0, shape)])
    for kind in ("msdf", "mtsdf", "psdf", "sdf"):
        atlas = bake_atlas(font, GlyphOptions(type=kind, size=40, range=4))
        (err,) = atlas_errors(atlas, magnify=8)
        assert err.error < 0.01, kind
        g = atlas.glyphs[0]
        inside = magnified_inside(atlas.image / 255.0, g.atlas, 8)
        h, w = inside.shape[0] // 8, inside.shape[1] // 8
        truth = reference_coverage(shape, 40 / 1000, g.plane[0] * 40, g.plane[1] * 40, w, h)
        edge = truth ^ ndimage.binary_erosion(truth, border_value=0)
        far = ndimage.distance_transform_edt(~edge)
        assert (far[inside != truth] <= 8).all(), kind


# ---------------------------------------------------------------------------------------------------- coloring
@needs_font
@pytest.mark.parametrize("strategy", ["notch", "simple", "inktrap", "distance"])
def test_edge_coloring_corners_share_one_channel(dejavu, strategy):
    """At every corner (direction turns by more than the threshold) the two edges share at most one channel, so the
    median keeps it sharp; contours without corners are white; every edge has at least two channels."""
    threshold = math.sin(3.0)
    for g in dejavu.glyphs:
        s = prepare(g.shape)
        if not s.segment_count:
            continue
        colors = edge_colors(s.points, s.degree, s.contour_start, 3.0, strategy)
        assert all(bin(int(c)).count("1") >= 2 for c in colors), chr(g.codepoint)
        for c in range(s.contour_count):
            a, b = s.contour_start[c], s.contour_start[c + 1]
            start = _directions(s.points[a:b], s.degree[a:b], 0.0)
            end = np.roll(_directions(s.points[a:b], s.degree[a:b], 1.0), 1, axis=0)
            dot = (start * end).sum(1)
            cross = np.abs(start[:, 0] * end[:, 1] - start[:, 1] * end[:, 0])
            corner = (dot <= 0) | (cross > threshold)
            col = colors[a:b]
            if not corner.any():
                assert (col == 7).all(), chr(g.codepoint)
                continue
            common = col & np.roll(col, 1)
            assert all(bin(int(x)).count("1") <= 1 for x in common[corner]), chr(g.codepoint)


def _splines(s, c, colors):
    """(colour, length) of each spline of contour c (edges between two corners), walked from the first corner;
    lengths from 256-point polylines, independent of the coloring's own estimate."""
    from baker.techniques.glyphs.segments import point_at

    a, b = s.contour_start[c], s.contour_start[c + 1]
    start = _directions(s.points[a:b], s.degree[a:b], 0.0)
    end = np.roll(_directions(s.points[a:b], s.degree[a:b], 1.0), 1, axis=0)
    corner = ((start * end).sum(1) <= 0) | (np.abs(start[:, 0] * end[:, 1] - start[:, 1] * end[:, 0]) > math.sin(3.0))
    first = np.flatnonzero(corner)
    out = []
    for k in range(b - a):
        i = (first[0] + k) % (b - a) if len(first) else k
        t = np.linspace(0.0, 1.0, 257)
        xy = np.array([point_at(s.points[a + i], int(s.degree[a + i]), float(u)) for u in t])
        length = float(np.linalg.norm(np.diff(xy, axis=0), axis=1).sum())
        if corner[i] or not out:
            out.append([int(colors[a + i]), 0.0])
        assert out[-1][0] == colors[a + i] or len(first) < 2  # a spline keeps one colour (teardrops: 3 zones)
        out[-1][1] += length
    return out, int(corner.sum())


def _notches(splines):
    """Indices of splines clearly (1%) shorter than both neighbours: the notches the ink-trap coloring protects."""
    n = len(splines)
    return [k for k in range(n) if splines[k][1] < 0.99 * min(splines[k - 1][1], splines[(k + 1) % n][1])]


def _one_channel(a, b):
    return bin(a & b).count("1") == 1


def test_inktrap_coloring_keeps_long_neighbours_of_a_notch_apart():
    """msdfgen's ink-trap rule (msdf-atlas-gen's default): on a contour with more than three corners, a spline shorter
    than both neighbours (an ink-trap notch) takes the channel pair its neighbours do not share, so removing it leaves
    a valid coloring: its two neighbours share exactly one channel, and it shares exactly one with each. Analytic
    shape: a right triangle whose top corner is cut by a short edge (lengths 10, 12.7, 1, 9)."""
    notch = [(0, 0), (10, 0), (1, 9), (0, 9)]
    contour = [(1, [notch[k], notch[(k + 1) % 4]]) for k in range(4)]
    s = prepare(from_contours([contour]))
    results = {}
    for strategy in ("simple", "inktrap"):
        colors = edge_colors(s.points, s.degree, s.contour_start, 3.0, strategy)
        splines, corners = _splines(s, 0, colors)
        assert corners == 4 and len(splines) == 4
        (k,) = _notches(splines)
        before, short, after = splines[k - 1][0], splines[k][0], splines[(k + 1) % 4][0]
        results[strategy] = _one_channel(before, after) and _one_channel(before, short) and _one_channel(short, after)
    assert results["inktrap"]
    assert not results["simple"]  # the rotation puts one colour on both sides of the notch: the rule is not trivial


def test_notch_coloring_applies_the_inktrap_rule_below_one_texel():
    """The default ``notch`` strategy: the triangle's cut (1 unit long) is a notch when a texel is larger than it
    (same colors as ``inktrap``, the notch rule holds), and a spline of its own when a texel is smaller (same colors
    as ``simple``, which puts one colour on both sides of it)."""
    notch = [(0, 0), (10, 0), (1, 9), (0, 9)]
    s = prepare(from_contours([[(1, [notch[k], notch[(k + 1) % 4]]) for k in range(4)]]))
    args = (s.points, s.degree, s.contour_start, 3.0)
    inktrap, simple = edge_colors(*args, "inktrap"), edge_colors(*args, "simple")
    assert (inktrap != simple).any()
    assert (edge_colors(*args, "notch", texel=2.0) == inktrap).all()
    assert (edge_colors(*args, "notch", texel=0.5) == simple).all()
    assert (edge_colors(*args, "notch", texel=1.0) == simple).all()  # exactly one texel long: resolved


@needs_font
def test_inktrap_coloring_notches_on_a_font(dejavu):
    """The same property on every contour of DejaVu Sans ASCII with more than three corners."""
    checked = 0
    for g in dejavu.glyphs:
        s = prepare(g.shape)
        if not s.segment_count:
            continue
        colors = edge_colors(s.points, s.degree, s.contour_start, 3.0, "inktrap")
        for c in range(s.contour_count):
            splines, corners = _splines(s, c, colors)
            if corners <= 3:
                continue
            n = len(splines)
            for k in _notches(splines):
                before, short, after = splines[k - 1][0], splines[k][0], splines[(k + 1) % n][0]
                assert _one_channel(before, after), chr(g.codepoint)
                assert _one_channel(before, short) and _one_channel(short, after), chr(g.codepoint)
                checked += 1
    assert checked > 20, checked


def test_distance_coloring_separates_close_splines():
    """By-distance coloring: two squares side by side, each a cycle of four splines, the right side of the first
    bulging (a quadratic) to 1 unit from the second's left side, the closest pair of splines that do not touch
    (everything else is >= 1.9 apart). Touching splines differ (corners), and that pair takes different colors
    too; with a cutoff below the gap only touching splines are constrained and the two get the same pair (so it is
    the distance rule that separates them)."""
    bulge = [(1, [(0, 0), (10, 0)]), (2, [(10, 0), (12, 5), (10, 10)]), (1, [(10, 10), (0, 10)]),
             (1, [(0, 10), (0, 0)])]
    right = [(1, [(12, 10), (12, 0)]), (1, [(12, 0), (22, 0)]), (1, [(22, 0), (22, 10)]), (1, [(22, 10), (12, 10)])]
    s = prepare(from_contours([bulge, right]))
    facing = (1, 4)  # first square's bulge, second square's left side (prepare keeps the segment order)
    assert s.degree[facing[0]] == 2 and (s.points[facing[1], :2, 0] == 12).all()
    for cutoff, apart in ((math.inf, True), (3.0, True), (0.5, False)):
        colors = edge_colors(s.points, s.degree, s.contour_start, 3.0, "distance", cutoff=cutoff)
        a, b = int(colors[facing[0]]), int(colors[facing[1]])
        assert (a != b) == apart, cutoff
        for c in range(2):  # each square is still a valid corner coloring
            col = colors[s.contour_start[c]: s.contour_start[c + 1]]
            assert all(_one_channel(int(x), int(y)) for x, y in zip(col, np.roll(col, 1))), cutoff


def test_distance_coloring_bounds_its_graph():
    """A hostile outline (one star contour of 1,100 corners: more splines than the dense graph may hold) is colored by
    the rotation instead; below the bound the graph coloring runs. Either way every corner keeps one channel."""
    from baker.techniques.glyphs.coloring import MAX_GRAPH_SPLINES

    for n, graph in ((MAX_GRAPH_SPLINES + 76, False), (60, True)):
        angle = np.arange(n) * 2 * np.pi / n
        radius = np.where(np.arange(n) % 2, 900.0, 1000.0)
        star = list(zip(radius * np.cos(angle), radius * np.sin(angle)))
        s = prepare(from_contours([[(1, [star[k], star[(k + 1) % n]]) for k in range(n)]]))
        colors = edge_colors(s.points, s.degree, s.contour_start, 3.0, "distance", cutoff=50.0)
        assert all(_one_channel(int(x), int(y)) for x, y in zip(colors, np.roll(colors, 1))), n
        simple = edge_colors(s.points, s.degree, s.contour_start, 3.0, "simple")
        assert (colors == simple).all() != graph, n


def test_msdf_bytes_deterministic_for_each_coloring():
    """Same outline and options -> byte-identical atlas, for every strategy (the rotation depends only on the
    contour order), and the two strategies differ on a contour with a notch."""
    notch = [(0, 0), (600, 0), (60, 540), (0, 540)]
    shape = from_contours([[(1, [notch[k], notch[(k + 1) % 4]]) for k in range(4)]])
    font = Font("synthetic", "synthetic", FontMetrics(1000, 900, -200, 1200, -100, 50),
                [Glyph(65, "A", 1, 700.0, shape)])
    images = {}
    for strategy in ("notch", "simple", "inktrap", "distance"):
        runs = [bake_atlas(font, GlyphOptions(type="msdf", size=40, range=4, coloring=strategy)).image.tobytes()
                for _ in range(2)]
        assert runs[0] == runs[1], strategy
        images[strategy] = runs[0]
    assert images["simple"] != images["inktrap"]


def _directions(points, degree, t):
    from baker.techniques.glyphs.segments import direction_at

    d = np.array([direction_at(p, int(k), t) for p, k in zip(points, degree)])
    return d / np.linalg.norm(d, axis=1, keepdims=True)


# ---------------------------------------------------------------------------------------------------- font input
def test_charsets():
    assert parse_charset("ascii") == list(range(0x20, 0x7F))
    assert parse_charset("0x41-0x43,U+00E9,66") == [0x41, 0x42, 0x43, 0xE9]
    assert parse_charset("str:hello") == [ord(c) for c in "helo"]
    with pytest.raises(Exception):
        parse_charset("0x50-0x40")


@needs_font
def test_charset_file_and_missing_glyphs_are_reported(tmp_path, capsys):
    chars = tmp_path / "chars.txt"
    chars.write_text("Aé\u4e00\uac00\n", "utf-8")
    font = load_font(FONT, f"file:{chars}")
    assert [g.codepoint for g in font.glyphs] == [0x41, 0xE9]
    assert font.missing == [0x4E00, 0xAC00]
    out = tmp_path / "a"
    assert main(["glyphs", str(FONT), "-o", str(out), "--charset", f"file:{chars}", "-q"]) == 0
    err = capsys.readouterr().err
    assert "2 character(s) have no glyph" in err and "U+4E00" in err and "U+AC00" in err


@needs_font
def test_kerning_from_gpos_agrees_with_legacy_kern_table(dejavu):
    """DejaVu Sans carries both: GPOS pair adjustment (what baker reads) and the legacy kern table (read here
    directly with fontTools). On ASCII they must tell the same story."""
    from fontTools.ttLib import TTFont

    tt = TTFont(str(FONT))
    cmap = tt.getBestCmap()
    legacy = {}
    for sub in tt["kern"].kernTables:
        for (a, b), v in sub.kernTable.items():
            legacy[(a, b)] = legacy.get((a, b), 0) + v
    ascii_legacy = {(x, y): v for x in range(0x20, 0x7F) for y in range(0x20, 0x7F)
                    if (v := legacy.get((cmap.get(x), cmap.get(y)), 0))}
    assert dejavu.kerning[(ord("A"), ord("V"))] < 0
    same = sum(abs(dejavu.kerning.get(k, 0) - v) < 1e-9 for k, v in ascii_legacy.items())
    assert same >= 0.9 * len(ascii_legacy), (same, len(ascii_legacy))


# ---------------------------------------------------------------------------------------------------- atlas files
MSDF_ATLAS_GEN_SCHEMA = {
    "type": "object",
    "required": ["atlas", "metrics", "glyphs", "kerning"],
    "properties": {
        "atlas": {"type": "object", "required": ["type", "distanceRange", "size", "width", "height", "yOrigin"],
                  "properties": {"type": {"enum": ["sdf", "psdf", "msdf", "mtsdf"]},
                                 "distanceRange": {"type": "number"}, "size": {"type": "number"},
                                 "width": {"type": "integer"}, "height": {"type": "integer"},
                                 "yOrigin": {"enum": ["bottom", "top"]}}},
        "metrics": {"type": "object", "required": ["emSize", "lineHeight", "ascender", "descender", "underlineY",
                                                   "underlineThickness"],
                    "additionalProperties": {"type": "number"}},
        "glyphs": {"type": "array", "items": {
            "type": "object", "required": ["unicode", "advance"],
            "properties": {"unicode": {"type": "integer"}, "advance": {"type": "number"},
                           "planeBounds": {"$ref": "#/$defs/bounds"}, "atlasBounds": {"$ref": "#/$defs/bounds"}},
            "dependentRequired": {"planeBounds": ["atlasBounds"], "atlasBounds": ["planeBounds"]}}},
        "kerning": {"type": "array", "items": {"type": "object", "required": ["unicode1", "unicode2", "advance"],
                                               "properties": {"unicode1": {"type": "integer"},
                                                              "unicode2": {"type": "integer"},
                                                              "advance": {"type": "number"}}}},
    },
    "$defs": {"bounds": {"type": "object", "required": ["left", "bottom", "right", "top"],
                         "additionalProperties": {"type": "number"}}},
}


@needs_font
def test_json_layout_and_plane_bounds_match_the_font(tmp_path):
    from fontTools.ttLib import TTFont
    from jsonschema import Draft202012Validator

    size, rng = 48, 4
    out = tmp_path / "dejavu"
    assert main(["glyphs", str(FONT), "-o", str(out), "--type", "mtsdf", "--size", str(size), "--range", str(rng),
                 "-q"]) == 0
    layout = json.loads((tmp_path / "dejavu.json").read_text())
    Draft202012Validator(MSDF_ATLAS_GEN_SCHEMA).validate(layout)
    image = read_image(tmp_path / "dejavu.png")
    assert image.shape == (layout["atlas"]["height"], layout["atlas"]["width"], 4) and image.dtype == np.uint8
    assert layout["atlas"]["type"] == "mtsdf" and layout["atlas"]["distanceRange"] == rng

    tt = TTFont(str(FONT))
    glyf, cmap, upem = tt["glyf"], tt.getBestCmap(), tt["head"].unitsPerEm
    em = layout["metrics"]["emSize"]
    tolerance = 1.0 / size + rng / size  # one pixel plus the range, in em
    boxes = []
    for g in layout["glyphs"]:
        ref = glyf[cmap[g["unicode"]]]
        assert g["advance"] == pytest.approx(tt["hmtx"][cmap[g["unicode"]]][0] / upem)
        if "planeBounds" not in g:
            assert not getattr(ref, "numberOfContours", 0)
            continue
        ref.recalcBounds(glyf)
        pb = g["planeBounds"]
        font_box = (ref.xMin / upem, ref.yMin / upem, ref.xMax / upem, ref.yMax / upem)
        for key, value in zip(("left", "bottom", "right", "top"), font_box):
            assert abs(pb[key] * em - value) <= tolerance, (chr(g["unicode"]), key, pb[key], value)
        assert pb["left"] < font_box[0] and pb["bottom"] < font_box[1]  # the box holds the glyph and its range
        assert pb["right"] > font_box[2] and pb["top"] > font_box[3]
        ab = g["atlasBounds"]
        assert 0 <= ab["left"] < ab["right"] <= layout["atlas"]["width"]
        assert 0 <= ab["bottom"] < ab["top"] <= layout["atlas"]["height"]
        # the quad and its texels have the same size: size px per em
        assert (pb["right"] - pb["left"]) * size == pytest.approx(ab["right"] - ab["left"])
        boxes.append(ab)
    # boxes do not overlap and keep the padding (1 texel) between them
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            apart = (a["right"] + 1 <= b["left"] or b["right"] + 1 <= a["left"] or a["top"] + 1 <= b["bottom"]
                     or b["top"] + 1 <= a["bottom"])
            assert apart
    assert any(k["unicode1"] == ord("A") and k["unicode2"] == ord("V") and k["advance"] < 0
               for k in layout["kerning"])


@needs_font
def test_outputs_are_deterministic_and_bmfont_layout(tmp_path):
    runs = []
    for i in range(2):
        out = tmp_path / f"run{i}"
        assert main(["glyphs", str(FONT), "-o", str(out), "--charset", "0x41-0x5A", "--pot", "true", "-q"]) == 0
        runs.append(((tmp_path / f"run{i}.png").read_bytes(), (tmp_path / f"run{i}.json").read_bytes()))
    assert runs[0] == runs[1]
    layout = json.loads(runs[0][1])
    w, h = layout["atlas"]["width"], layout["atlas"]["height"]
    assert w & (w - 1) == 0 and h & (h - 1) == 0

    out = tmp_path / "bm"
    assert main(["glyphs", str(FONT), "-o", str(out), "--format", "bmfont", "--charset", "str:AV", "--square",
                 "true", "-q"]) == 0
    bm = json.loads((tmp_path / "bm.json").read_text())
    assert bm["pages"] == ["bm.png"] and bm["common"]["scaleW"] == bm["common"]["scaleH"]
    assert {c["char"] for c in bm["chars"]} == {"A", "V"}
    assert bm["distanceField"] == {"fieldType": "msdf", "distanceRange": 4.0}
    assert any(k["first"] == 65 and k["second"] == 86 and k["amount"] < 0 for k in bm["kernings"])


def test_packing_is_tight_and_valid():
    rng = np.random.default_rng(1)
    sizes = [tuple(int(v) for v in s) for s in rng.integers(3, 40, (120, 2))]
    positions, w, h = pack(sizes, padding=2)
    occupied = np.zeros((h, w), np.int32)
    for (x, y), (bw, bh) in zip(positions, sizes):
        assert x >= 2 and y >= 2 and x + bw <= w - 2 and y + bh <= h - 2
        occupied[y - 1: y + bh + 1, x - 1: x + bw + 1] += 1  # each box with half the padding around it
    assert occupied.max() == 1
    assert sum(bw * bh for bw, bh in sizes) / (w * h) > 0.6
    _, sw, sh = pack(sizes, padding=2, square=True, pot=True)
    assert sw == sh and sw & (sw - 1) == 0


# ---------------------------------------------------------------------------------------------------- glTF
@needs_font
def test_text_label_validates(tmp_path):
    out = tmp_path / "label.glb"
    assert main(["text", "Hello, World!\nglyphs & $", "--font", str(FONT), "-o", str(out), "--align", "center",
                 "--outline-width", "0.05", "-q"]) == 0
    report = validate_file(out, khronos=False)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert not [m for m in report["issues"]["messages"] if m["code"] == "BAKER_UNKNOWN_EXTENSION"]
    assert_khronos_clean(out)
    gltf_out = tmp_path / "label.gltf"
    assert main(["text", "Hi", "--font", str(FONT), "-o", str(gltf_out), "--type", "sdf", "-q"]) == 0
    assert validate_file(gltf_out, khronos=False)["issues"]["numErrors"] == 0
    assert_khronos_clean(gltf_out)


@needs_font
def test_text_layout_round_trip(tmp_path):
    """The quads in the file are where advances and kerning put them, and sample the right atlas boxes."""
    from baker.gltf.document import GltfDocument

    out = tmp_path / "av.glb"
    assert main(["text", "AV", "--font", str(FONT), "-o", str(out), "--em-size", "2", "-q"]) == 0
    doc = GltfDocument.load(out)
    root = doc.json["extensions"]["BAKER_glyph_atlas"]["fonts"][0]
    unicode = doc.accessor(root["glyphs"]["unicode"])
    advance = doc.accessor(root["glyphs"]["advance"])
    plane = doc.accessor(root["glyphs"]["planeBounds"])
    pairs, kern = doc.accessor(root["kerning"]["pairs"]), doc.accessor(root["kerning"]["advance"])
    ia, iv = list(unicode).index(ord("A")), list(unicode).index(ord("V"))
    k = kern[[tuple(p) == (ord("A"), ord("V")) for p in pairs].index(True)]
    prim = doc.json["meshes"][0]["primitives"][0]
    pos = doc.accessor(prim["attributes"]["POSITION"]).reshape(2, 4, 3)
    assert pos[0, 0, 0] == pytest.approx(plane[ia, 0] * 2, abs=1e-6)
    assert pos[1, 0, 0] == pytest.approx((advance[ia] + k + plane[iv, 0]) * 2, abs=1e-6)
    assert k < 0
    text = doc.json["nodes"][0]["extensions"]["BAKER_text"]
    assert text["text"] == "AV" and text["emSize"] == 2.0


def test_validator_catches_broken_atlas(tmp_path):
    if not FONT.is_file():
        pytest.skip("font missing")
    from baker.gltf.document import GltfDocument

    out = tmp_path / "label.glb"
    assert main(["text", "ok", "--font", str(FONT), "-o", str(out), "-q"]) == 0
    doc = GltfDocument.load(out)
    font = doc.json["extensions"]["BAKER_glyph_atlas"]["fonts"][0]
    font["width"] += 3
    doc.json["nodes"][0]["extensions"]["BAKER_text"]["text"] = "ok?"
    # without the shaped run a runtime lays the text out by code point: "?" is in no glyph table
    del doc.json["nodes"][0]["extensions"]["BAKER_text"]["glyphs"]
    bad = tmp_path / "bad.glb"
    doc.save(bad)
    report = validate_file(bad, khronos=False)
    codes = {m["code"] for m in report["issues"]["messages"]}
    assert "BAKER_GLYPH_ATLAS_SIZE" in codes and "BAKER_TEXT_GLYPH_MISSING" in codes


def test_bad_font_is_one_line_exit_2(tmp_path, capsys):
    bogus = tmp_path / "bogus.ttf"
    bogus.write_bytes(b"not a font")
    assert main(["glyphs", str(bogus), "-o", str(tmp_path / "x")]) == 2
    assert main(["glyphs", str(tmp_path / "missing.ttf"), "-o", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and all(line.startswith("baker: error:") for line in err)
    assert not list(tmp_path.glob("x*"))


def test_cff_font_with_cubic_outlines(tmp_path):
    """An OpenType/CFF font (cubic Beziers), built here with fontTools: read, baked and scored like TrueType."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.t2CharStringPen import T2CharStringPen

    def ring(pen, cx, cy, r, clockwise):
        k = 0.5522847498 * r
        pts = [(cx + r, cy), (cx + r, cy + k), (cx + k, cy + r), (cx, cy + r), (cx - k, cy + r), (cx - r, cy + k),
               (cx - r, cy), (cx - r, cy - k), (cx - k, cy - r), (cx, cy - r), (cx + k, cy - r), (cx + r, cy - k)]
        if clockwise:
            pts = [pts[0]] + pts[1:][::-1]
        pen.moveTo(pts[0])
        for i in range(1, 12, 3):
            pen.curveTo(pts[i], pts[i + 1], pts[(i + 2) % 12])
        pen.closePath()

    fb = FontBuilder(1000, isTTF=False)
    fb.setupGlyphOrder([".notdef", "O"])
    fb.setupCharacterMap({ord("O"): "O"})
    pen = T2CharStringPen(700, None)
    ring(pen, 350, 350, 330, False)
    ring(pen, 350, 350, 190, True)
    charstrings = {"O": pen.getCharString(), ".notdef": T2CharStringPen(500, None).getCharString()}
    fb.setupCFF("Test", {"FullName": "Test"}, charstrings, {})
    fb.setupHorizontalMetrics({"O": (700, 20), ".notdef": (500, 0)})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Test", "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()
    path = tmp_path / "test.otf"
    fb.save(str(path))

    font = load_font(path, "str:O")
    assert set(font.glyphs[0].shape.degree.tolist()) == {3}
    for kind in ("msdf", "sdf"):
        atlas = bake_atlas(font, GlyphOptions(type=kind, size=48, range=4))
        (err,) = atlas_errors(atlas, magnify=8, topology=True)
        assert err.error < 0.01 and err.components == (1, 1) and err.holes == (2, 2), (kind, err)


# ---------------------------------------------------------------------------------------------------- error correction
CJK = Path("/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc")


def test_edge_priority_correction_beats_no_correction_and_its_own_stages_on_cjk(monkeypatch):
    """Noto Sans CJK glyphs with tight inner stroke corners (the ones where baker trailed msdfgen most), 32 px/em,
    wrongly covered pixels against the exact outline: the default error correction (msdfgen's edge-priority method,
    corner and edge protection plus the per-neighbour artifact classifier) leaves fewer than no correction, than the
    same with msdfgen's distance check at edges added, and than the former 5 x 5 grid check."""
    import functools

    import baker.techniques.glyphs.correction as correction
    import baker.techniques.glyphs.msdf as msdf
    from baker.techniques.glyphs.outline import load_fonts

    assert CJK.is_file(), f"{CJK} missing (scripts/test installs fonts-noto-cjk)"
    font = load_fonts([(str(CJK), 2)], [ord(c) for c in "叠嘻锹篷檐籍谴悲湃掐鹰"])
    options = dict(type="msdf", size=32, range=4)

    def wrong(**kw):
        atlas = bake_atlas(font, GlyphOptions(**options, **kw))
        return sum(e.wrong for e in atlas_errors(atlas))

    default, uncorrected = wrong(), wrong(error_correction=False)
    monkeypatch.setattr(msdf, "correct_edge_priority",
                        functools.partial(correction.correct_edge_priority, distance_check=True))
    distance_checked = wrong()
    monkeypatch.undo()

    def grid(batch, corners, values, distance_range):
        # the former check on the clamped field, with the exact distances the kernel computed
        true, _ = msdf.distance_fields(batch)
        np.clip(values, 0.0, 1.0, out=values)
        correction.correct_errors(batch, corners, values, np.clip(0.5 + true / distance_range, 0.0, 1.0),
                                  distance_range)

    monkeypatch.setattr(msdf, "correct_edge_priority", grid)
    former = wrong()
    assert default < uncorrected, (default, uncorrected)
    assert default < distance_checked, (default, distance_checked)
    assert default < former, (default, former)
