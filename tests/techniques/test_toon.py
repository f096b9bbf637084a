"""Toon ramps (hard and soft bands) and X-Toon detail maps (Barla et al. 2006): the ramp's bands against their
closed form, the ``toon-ramp`` command's files, and the README example against the schema. The glTF written by a
tam + toon bake is checked in test_tam.py."""
from __future__ import annotations

import json

import numpy as np
import pytest
from jsonschema import Draft202012Validator

from baker import validate
from baker.data import SCHEMA_ROOT
from baker.techniques.toon.options import ToonOptions
from baker.techniques.toon.kernel import band_value, toon_ramp, xtoon_map
from baker.cli import main as cli
from baker.gltf.images import read_image


def test_hard_ramp_has_n_flat_bands():
    ramp = toon_ramp(ToonOptions(bands=4, shadow=0.2, width=64))
    values = np.unique(ramp)
    np.testing.assert_allclose(values, [0.2, 0.2 + 0.8 / 3, 0.2 + 1.6 / 3, 1.0])
    assert np.all(np.diff(ramp) >= 0) and np.count_nonzero(np.diff(ramp)) == 3
    # band k covers u in [k/4, (k+1)/4)
    u = (np.arange(64) + 0.5) / 64
    np.testing.assert_array_equal(np.searchsorted(values, ramp), np.floor(u * 4).astype(int))


def test_soft_ramp_is_smooth_and_monotone():
    hard = toon_ramp(ToonOptions(bands=3, softness=0.0, width=512))
    soft = toon_ramp(ToonOptions(bands=3, softness=0.5, width=512))
    assert np.all(np.diff(soft) >= 0)
    assert np.abs(np.diff(soft)).max() < np.abs(np.diff(hard)).max() / 10  # no jumps
    # away from the transitions the bands are the same
    u = (np.arange(512) + 0.5) / 512
    far = np.abs(u * 3 - np.round(u * 3)) > 0.3
    np.testing.assert_allclose(soft[far], hard[far])
    assert band_value(0.5, 3, 0.5, 0.25) == pytest.approx(0.625)


def test_xtoon_map_loses_contrast_with_detail():
    options = ToonOptions(bands=3, xtoon="orientation", height=16, width=128, min_contrast=0.2)
    m = xtoon_map(options)
    ramp = toon_ramp(ToonOptions(bands=3, width=128))
    assert np.abs(m[0] - ramp).mean() < 0.03  # the top row (D ~ 1) is the toon ramp itself
    contrast = m.max(axis=1) - m.min(axis=1)
    assert np.all(np.diff(contrast) < 0)  # detail D falls down the rows: less contrast
    assert contrast[-1] < 0.25 * contrast[0]
    assert np.abs(np.diff(m[-1])).max() < np.abs(np.diff(m[0])).max()


def test_toon_ramp_command(tmp_path):
    assert cli(["toon-ramp", "-o", str(tmp_path), "-q", "--toon-bands", "5"]) == 0
    manifest = json.loads((tmp_path / "toon.json").read_text())
    pixels = read_image(tmp_path / manifest["file"])
    assert pixels.shape == (1, 256, 1) and len(np.unique(pixels)) == 5
    assert cli(["toon-ramp", "-o", str(tmp_path / "x"), "-q", "--toon-xtoon", "depth", "--toon-height", "32"]) == 0
    assert read_image(tmp_path / "x" / "xtoon_map.png").shape == (32, 256, 1)


def test_readme_example_is_valid():
    name = "BAKER_toon_ramp"
    schema = json.loads(validate.schema_registry()[(name, "material")].read_text())
    readme = (SCHEMA_ROOT / name / "README.md").read_text()
    block = readme.split("```json")[1].split("```")[0].strip()
    example = json.loads(block if block.startswith("{") else "{" + block + "}")  # a whole glTF, or a fragment
    ext = (example["materials"][0]["extensions"] if "materials" in example else example["extensions"])[name]
    assert not list(Draft202012Validator(schema).iter_errors(ext))
