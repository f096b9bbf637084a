"""``baker hair-lut -o DIR`` (:func:`run_hair_lut`): the fibre tables and their sidecar, one atomic group."""
from __future__ import annotations

import sys
from pathlib import Path

from baker.errors import BakerError
from baker.options import from_args
from baker.techniques.hair_shading.options import HairShadingOptions


def run_hair_lut(args) -> int:
    from baker.gltf.atomic import write_files_atomic
    from baker.techniques.hair_shading.extension import lut_files
    from baker.techniques.hair_shading.tables import bake_tables, dual_scattering_table

    try:
        options = from_args(HairShadingOptions, "hair", args)
    except ValueError as exc:
        raise BakerError(None, str(exc)) from None
    folder = Path(args.output)
    if folder.exists() and not folder.is_dir():
        raise BakerError(folder, "not a folder (baker hair-lut writes a folder of tables)")
    folder.mkdir(parents=True, exist_ok=True)
    tables = bake_tables(options.beta_m, options.beta_n, options.eta, options.m_size, options.phi_size,
                         options.theta_size, options.slices, options.offsets)
    dual = dual_scattering_table(options.beta_m, options.beta_n, options.eta, options.alpha, options.theta_size,
                                 options.slices, options.offsets)
    files = [(folder / name, data) for name, data in lut_files(tables, options, dual)]
    write_files_atomic(files)  # the sidecar last: all new files or all earlier ones
    if not args.quiet:
        sizes = ", ".join(f"{p.name} {len(d) // 1024} KiB" for p, d in files)
        print(f"hair tables beta_m {options.beta_m} beta_n {options.beta_n} eta {options.eta} -> {folder}: {sizes}",
              file=sys.stderr)
    return 0
