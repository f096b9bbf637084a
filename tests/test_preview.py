"""``baker preview``: panels render with the runtime shaders and show their effect (pixel statistics per panel)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import baker
from baker.cli import main
from baker.io.images import read_image
from baker.pipeline import save
from baker.preview import BACKGROUND, preview

SPOT = Path(__file__).parents[1] / "examples" / "spot" / "spot.obj"


@pytest.fixture(scope="module")
def baked_spot(tmp_path_factory):
    out = tmp_path_factory.mktemp("preview") / "spot.glb"
    save(baker.bake(SPOT, options={"thickness": {"rays": 32, "per_texel": False}}), out)
    return out


def _panel(result, name):
    for n, _, (y, x, size) in result.panels:
        if n == name:
            return result.sheet[y: y + size, x: x + size].astype(np.float64) / 255.0
    raise AssertionError(f"no panel {name}")


def _covered(image):
    return np.abs(image - np.array(BACKGROUND)).max(axis=2) > 0.02


def test_translucency_is_brighter_where_thin(baked_spot):
    result = preview(baked_spot, size=256, azimuth=150, elevation=15)
    assert [n for n, _, _ in result.panels] == ["lambert", "thickness", "translucency"]
    thickness, translucent = _panel(result, "thickness"), _panel(result, "translucency")
    mask = _covered(_panel(result, "lambert"))
    assert 0.05 < mask.mean() < 0.8  # the model fills a sensible part of the frame
    # the thickness panel is mix(orange, blue, t): blue grows with normalized thickness
    t = (thickness[..., 2] - 0.1) / 0.8
    brightness = translucent.mean(axis=2)
    corr = np.corrcoef(t[mask], brightness[mask])[0, 1]
    assert corr < -0.3, corr
    thin, thick = mask & (t < 0.3), mask & (t > 0.7)
    assert thin.sum() > 50 and thick.sum() > 50
    assert brightness[thin].mean() > 1.5 * brightness[thick].mean()


def test_panels_need_their_data(tmp_path):
    import trimesh

    src = tmp_path / "plain.glb"
    trimesh.creation.icosphere(subdivisions=2).export(str(src))
    result = preview(src, size=64)
    assert [n for n, _, _ in result.panels] == ["lambert"]


def test_cli_writes_png_and_rejects_bad_output(baked_spot, tmp_path):
    out = tmp_path / "sheet.png"
    assert main(["preview", str(baked_spot), "-o", str(out), "--size", "96", "-q"]) == 0
    image = read_image(out)
    assert image.shape[1] == 3 * 96 and image.shape[2] == 3
    assert main(["preview", str(baked_spot), "-o", str(tmp_path / "sheet.glb"), "-q"]) == 2
    assert not (tmp_path / "sheet.glb").exists()
