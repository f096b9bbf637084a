"""The host wrappers of ``runtime-shaders/hosts/`` (read by ``baker preview`` and these tests): each compiles as
GLSL ES 3.00 and 3.30 core with the modules it calls and its placeholders filled the way the preview fills them."""
from __future__ import annotations

import pytest

from .glsl import HEADERS, REPO, assert_compiles, read_host, read_module

# host -> (runtime modules it calls, placeholder parts)
HOSTS = {
    "preview_surface.vert.glsl": (["baker_edges.glsl"], {
        "body": "v_bary = baker_barycentric(gl_VertexID);\n    v_mask = int(a_mask + 0.5);"}),
    "preview_surface.frag.glsl": (["baker_edges.glsl"], {
        "line": "uniform vec3 u_ink;\nuniform float u_width;", "inputs": "in vec3 v_bary;\nflat in int v_mask;",
        "body": "color = mix(N, u_ink, baker_wireframe(v_bary, fwidth(v_bary), v_mask, u_width, 0.0).x);"}),
    "edges_fin.vert.glsl": (["baker_edges.glsl"], {}),
    "solid.frag.glsl": ([], {}),
    "text.vert.glsl": ([], {}),
    "text.frag.glsl": (["baker_text.glsl"], {}),
    "hair_ribbon.vert.glsl": (["baker_hair.glsl"], {}),
    "hair_kajiya_kay.frag.glsl": (["baker_hair.glsl"], {}),
    "hair_ribbon_shading.vert.glsl": (["baker_hair.glsl", "baker_hair_shading.glsl"], {}),
    "hair_shading.frag.glsl": (["baker_hair_shading.glsl"], {}),
    "preview_lines.vert.glsl": ([], {}),
    "preview_lines.frag.glsl": ([], {}),
}


def test_every_host_is_listed():
    assert sorted(p.name for p in (REPO / "runtime-shaders" / "hosts").glob("*.glsl")) == sorted(HOSTS)


@pytest.mark.parametrize("name", sorted(HOSTS))
@pytest.mark.parametrize("version", sorted(HEADERS))
def test_host_compiles(glslang_validator, tmp_path, version, name):
    modules, parts = HOSTS[name]
    text = HEADERS[version] + read_host(name, modules="\n".join(read_module(m) for m in modules), **parts)
    stage = "vert" if ".vert." in name else "frag"
    assert_compiles(glslang_validator, tmp_path, version, name.split(".")[0], stage, text)
