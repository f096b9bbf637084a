"""The hair material of strand sets (``baker hair``, ``baker guides``): ``BAKER_hair_shading`` with its tables, and
per strand vertex the melanin variation (``_HAIR_MELANIN``), the rest-pose occlusion (``_HAIR_OCCLUSION``) and the
fibre counts (``_HAIR_FIBRES_POS``/``_NEG``) of :mod:`.occlusion`, computed over every strand set together (the
groom is guides and children)."""
from __future__ import annotations

import numpy as np

from baker.techniques.hair_shading.extension import (FIBRES_NEGATIVE, FIBRES_POSITIVE, MELANIN, OCCLUSION,
                                                     add_hair_material)


def strand_widths(positions: np.ndarray, width_scale: np.ndarray, root_width: float, tip_width: float) -> np.ndarray:
    """(S, V) widths as BAKER_hair and USD define them: mix(rootWidth, tipWidth, param) x widthScale."""
    s, v = positions.shape[:2]
    param = np.linspace(0.0, 1.0, v)
    return (root_width + (tip_width - root_width) * param)[None, :] * np.asarray(width_scale, float)[:, None]


def strand_attributes(options, strand_sets, root_width: float, tip_width: float, scalp=None, seed: int = 0):
    """([{attribute: per-vertex values}] per strand set, extension keywords for :func:`add_hair_material`).

    ``strand_sets``: objects with ``positions`` (S, V, 3) and ``width_scale`` (S,), all with the same V;
    ``scalp``: (vertices, faces) in the strands' space, or None."""
    counts = [len(s.positions) for s in strand_sets]
    out = [{} for _ in strand_sets]
    kwargs = {}
    rng = np.random.default_rng(seed + 4049)  # independent of the growth's stream
    if options.melanin_variation > 0 and options.rgb is None:
        kwargs["melanin"] = True
        for attrs, s in zip(out, strand_sets):
            factor = np.exp(options.melanin_variation * rng.standard_normal(len(s.positions)))
            melanin = np.stack([options.eumelanin * factor, options.pheomelanin * factor], -1)
            attrs[MELANIN] = np.repeat(melanin, s.positions.shape[1], axis=0).astype(np.float32)
    if options.occlusion_rays > 0 and sum(counts):
        from baker.techniques.hair_shading.occlusion import strand_occlusion

        positions = np.concatenate([np.asarray(s.positions, np.float64) for s in strand_sets])
        widths = np.concatenate([strand_widths(s.positions, s.width_scale, root_width, tip_width)
                                 for s in strand_sets])
        visibility, positive, negative, info = strand_occlusion(positions, widths, rays=options.occlusion_rays,
                                                                scalp=scalp, seed=seed)
        v = positions.shape[1]
        bounds = np.cumsum([0] + counts) * v
        for i, attrs in enumerate(out):
            part = slice(bounds[i], bounds[i + 1])
            attrs[OCCLUSION] = visibility[part]
            attrs[FIBRES_POSITIVE] = positive[part]
            attrs[FIBRES_NEGATIVE] = negative[part]
        kwargs["occlusion"] = {"attribute": OCCLUSION, "rays": info["rays"], "distance": info["distance"],
                               "scalp": info["scalp"]}
        kwargs["fibreCount"] = {"basis": "ambientCube", "positive": FIBRES_POSITIVE, "negative": FIBRES_NEGATIVE,
                                "rays": info["rays"], "distance": info["countDistance"]}
    return out, kwargs


def hair_material(doc, options, strand_sets, root_width: float, tip_width: float, scalp=None, seed: int = 0):
    """(material index, [{attribute: values}] per strand set): the strands' hair material added to ``doc``."""
    attributes, kwargs = strand_attributes(options, strand_sets, root_width, tip_width, scalp, seed)
    fibre_count = kwargs.pop("fibreCount", None)
    material = add_hair_material(doc, options, fibre_count=fibre_count, **kwargs)
    return material, attributes
