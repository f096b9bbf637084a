"""Import side, before Blender's glTF importer builds a mesh: one width for the mesh's custom attributes.

Blender 4.5's importer (``io_scene_gltf2/blender/imp/mesh.py`` ``do_primitives``) pairs a mesh's custom attributes
(``_NAME``) with their arrays through a Python ``set``'s order, so attributes of different widths in one mesh fail to
import at random (``ValueError`` from ``np.concatenate``, depending on ``PYTHONHASHSEED``). baker's ``native``
attribute layout writes each attribute at its width (``_THICKNESS`` SCALAR next to ``_PRINCIPAL_DIRECTION`` VEC3), and
a user's own attributes may differ from baker's. This hook points every narrower FLOAT custom attribute of such a
mesh at an in-memory copy padded with zeros to the mesh's widest, so the stock code meets one width: the attribute
arrives in Blender with its values in the first components (as baker's ``blender`` layout writes it). The file on
disk is not changed (the rest of the add-on reads the file itself).
"""
from __future__ import annotations

import numpy as np

FLOAT = 5126
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
TYPES = {count: kind for kind, count in COMPONENTS.items()}


def padded_accessor(gltf_importer, index: int, width: int) -> int:
    """A new in-memory accessor holding accessor ``index``'s values padded with zeros to ``width`` components."""
    from io_scene_gltf2.io.com.gltf2_io import Accessor, Buffer, BufferView
    from io_scene_gltf2.io.imp.gltf2_io_binary import BinaryData

    data = gltf_importer.data
    values = np.asarray(BinaryData.decode_accessor(gltf_importer, index), np.float32)
    values = values.reshape(len(values), -1)
    out = np.zeros((len(values), width), np.float32)
    out[:, :values.shape[1]] = values
    raw = out.astype("<f4").tobytes()
    if data.buffers is None:
        data.buffers = []
    data.buffers.append(Buffer.from_dict({"byteLength": len(raw)}))
    gltf_importer.buffers[len(data.buffers) - 1] = memoryview(raw)
    data.buffer_views.append(BufferView.from_dict({"buffer": len(data.buffers) - 1, "byteLength": len(raw)}))
    data.accessors.append(Accessor.from_dict({"bufferView": len(data.buffer_views) - 1, "componentType": FLOAT,
                                              "count": len(out), "type": TYPES[width]}))
    return len(data.accessors) - 1


def one_width(gltf_importer, pymesh) -> None:
    """Give the FLOAT custom attributes of ``pymesh`` (a glTF mesh as the importer parsed it) the width of its
    widest one, when they differ; and KHR_mesh_quantization's normalized-integer custom attributes (what
    ``gltf-transform quantize`` and ``meshopt`` write) FLOAT copies of their values, which the stock importer
    otherwise skips (it makes Blender attributes of FLOAT, INT and colour data only)."""
    accessors = gltf_importer.data.accessors
    custom = [(prim, name, index) for prim in pymesh.primitives for name, index in (prim.attributes or {}).items()
              if name.startswith("_")]
    widths = {COMPONENTS.get(accessors[index].type, 0) for _, _, index in custom}
    quantized = any(accessors[index].normalized and accessors[index].component_type != FLOAT for _, _, index in custom)
    if (len(widths) < 2 and not quantized) or 0 in widths:
        return  # one width already, or matrices the importer skips anyway
    widest = max(widths)
    copies = {}
    for prim, name, index in custom:
        accessor = accessors[index]
        dequantize = accessor.normalized and accessor.component_type != FLOAT  # decode_accessor gives c / max
        if not dequantize and (accessor.component_type != FLOAT or accessor.normalized
                               or COMPONENTS[accessor.type] == widest):
            continue
        if index not in copies:
            copies[index] = padded_accessor(gltf_importer, index, widest)
        prim.attributes[name] = copies[index]
