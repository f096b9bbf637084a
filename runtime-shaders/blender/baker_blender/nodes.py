"""Shader node groups that reproduce baker's runtime shaders in EEVEE/Cycles nodes, and their wiring into an
imported material: each group's shader goes through a Mix Shader (factor 0) after whatever fed the Material Output,
so the untouched material renders exactly as before; raise the factor to see the baked technique.

- ``BAKER Translucency`` (runtime-shaders/baker_translucency.glsl, RTR4 eq. 14.30 + Barre-Brisebois & Bouchard 2011):
  transmittance t = exp(-thickness / attenuationDistance) from ``_THICKNESS`` (x), a Translucent BSDF of colour
  c_ss * t * scale (Blender's lights supply the (v . -l) lobe) plus c_ss * t * ambient as emission.
- ``BAKER Skin LUT`` (baker_skin.glsl, Penner & Borshukov 2011): the LUT texel at u = N.L remapped from ndotlRange,
  v = curvature * curvatureScale remapped from curvatureRange, as emission; N.L against the group's Light Direction.
- ``BAKER Toon Ramp`` (baker_toon.glsl): the ramp texel at u = N.L * 0.5 + 0.5, as emission.
- ``BAKER Hatching`` (baker_hatching.glsl, Praun et al. 2001): the first level's tone textures on TEXCOORD_0, its
  first texture as emission (the tones are in the material's ``baker_tam_tones``).
- ``BAKER Fur Shell`` (baker_fur.glsl, Lengyel et al. 2001): the innermost shell texture tiled over TEXCOORD_0,
  its coverage as alpha over a transparent BSDF.
- ``BAKER Diffuse Normals`` (baker_normal_blur.glsl, RTR4 14.6.2): the three diffuse normal maps of BAKER_normal_blur
  through tangent-space Normal Map nodes, one Diffuse BSDF per colour channel of the base colour, summed.
- ``BAKER Caustics Coordinates`` + ``BAKER Caustics`` (baker_caustics.glsl, RTR4 14.5.3): the first caustic frame
  projected from the world position along the refracted sun direction onto the baked depth (baker_caustics_uv in
  Blender's Z-up axes) and the depth fade; its irradiance E = texel x intensityScale and an emission of
  Sunlit x (E - 1) x strength x fade (negative in the dark cells: the caustic moves light, it does not add it). Unlike the groups above it is added to the surface
  (Add Shader), so the caustics show as imported; the node ``BAKER caustics add`` is the one to mute.
"""
from __future__ import annotations

import bpy

MIX_PREFIX = "BAKER mix "


def new_group(name: str, inputs: list, outputs: list):
    group = bpy.data.node_groups.get(name)
    if group is not None:
        return group, None
    group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for socket_name, kind, default in inputs:
        socket = group.interface.new_socket(socket_name, in_out="INPUT", socket_type=kind)
        if default is not None:
            socket.default_value = default
    for socket_name, kind in outputs:
        group.interface.new_socket(socket_name, in_out="OUTPUT", socket_type=kind)
    return group, (group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput"))


def math_node(tree, operation: str, a, b=None):
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = operation
    for i, value in enumerate((a, b)):
        if value is None:
            continue
        if isinstance(value, (int, float)):
            node.inputs[i].default_value = value
        else:
            tree.links.new(value, node.inputs[i])
    return node.outputs[0]


def vector_scale(tree, color, factor):
    node = tree.nodes.new("ShaderNodeVectorMath")
    node.operation = "SCALE"
    tree.links.new(color, node.inputs[0])
    if isinstance(factor, (int, float)):
        node.inputs["Scale"].default_value = factor
    else:
        tree.links.new(factor, node.inputs["Scale"])
    return node.outputs[0]


def translucency_group():
    group, io = new_group("BAKER Translucency", [
        ("Thickness", "NodeSocketFloat", 0.0), ("Subsurface Color", "NodeSocketColor", (1.0, 0.4, 0.3, 1.0)),
        ("Attenuation Distance", "NodeSocketFloat", 1.0), ("Scale", "NodeSocketFloat", 1.0),
        ("Ambient", "NodeSocketFloat", 0.0)], [("Shader", "NodeSocketShader"), ("Transmittance", "NodeSocketFloat")])
    if io is None:
        return group
    tree, (gin, gout) = group, io
    ratio = math_node(tree, "DIVIDE", gin.outputs["Thickness"], math_node(tree, "MAXIMUM", gin.outputs["Attenuation Distance"], 1e-9))
    transmittance = math_node(tree, "EXPONENT", math_node(tree, "MULTIPLY", ratio, -1.0))
    tinted = vector_scale(tree, gin.outputs["Subsurface Color"], transmittance)
    translucent = tree.nodes.new("ShaderNodeBsdfTranslucent")
    tree.links.new(vector_scale(tree, tinted, gin.outputs["Scale"]), translucent.inputs["Color"])
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(vector_scale(tree, tinted, gin.outputs["Ambient"]), emission.inputs["Color"])
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(translucent.outputs[0], add.inputs[0])
    tree.links.new(emission.outputs[0], add.inputs[1])
    tree.links.new(add.outputs[0], gout.inputs["Shader"])
    tree.links.new(transmittance, gout.inputs["Transmittance"])
    return group


def diffuse_normals_group():
    """Per-channel diffuse (BAKER_normal_blur, baker_normal_blur.glsl): three Diffuse BSDFs, one per colour channel
    of the base colour, each shaded with its own blurred normal; their sum is the diffuse term of skin whose red
    light scatters furthest (RTR4 14.6.2). Specular stays with the material's own BSDF and normal map."""
    group, io = new_group("BAKER Diffuse Normals", [
        ("Base Color", "NodeSocketColor", (0.8, 0.8, 0.8, 1.0)), ("Normal Red", "NodeSocketVector", None),
        ("Normal Green", "NodeSocketVector", None), ("Normal Blue", "NodeSocketVector", None)],
        [("Shader", "NodeSocketShader")])
    if io is None:
        return group
    tree, (gin, gout) = group, io
    separate = tree.nodes.new("ShaderNodeSeparateColor")
    tree.links.new(gin.outputs["Base Color"], separate.inputs[0])
    shaders = []
    for channel, socket in (("Red", "Normal Red"), ("Green", "Normal Green"), ("Blue", "Normal Blue")):
        combine = tree.nodes.new("ShaderNodeCombineColor")
        tree.links.new(separate.outputs[channel], combine.inputs[channel])
        bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
        tree.links.new(combine.outputs[0], bsdf.inputs["Color"])
        tree.links.new(gin.outputs[socket], bsdf.inputs["Normal"])
        shaders.append(bsdf.outputs[0])
    first = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(shaders[0], first.inputs[0])
    tree.links.new(shaders[1], first.inputs[1])
    second = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(first.outputs[0], second.inputs[0])
    tree.links.new(shaders[2], second.inputs[1])
    tree.links.new(second.outputs[0], gout.inputs["Shader"])
    return group


def uv_map_names(mat) -> list:
    """The UV maps of the first mesh using ``mat``, in TEXCOORD order (the glTF importer adds TEXCOORD_n as the
    n-th UV map)."""
    users = [obj for obj in bpy.data.objects
             if obj.type == "MESH" and any(m is not None and m.name == mat.name for m in obj.data.materials)]
    return [layer.name for layer in users[0].data.uv_layers] if users else []


def add_diffuse_normals(mat, blur: dict, textures: dict, location) -> None:
    """The three diffuse maps (Non-Color) through tangent-space Normal Map nodes on the normal texture's UV set into
    ``BAKER Diffuse Normals``, mixed in after the surface at factor 0 (raise it to see the blurred diffuse)."""
    tree = mat.node_tree
    x, y = location
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = diffuse_normals_group()
    node.name = node.label = "BAKER Diffuse Normals"
    node.location = (x + 300, y)
    principled = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if principled is not None:
        base = principled.inputs["Base Color"]
        if base.links:
            tree.links.new(base.links[0].from_socket, node.inputs["Base Color"])
        else:
            node.inputs["Base Color"].default_value = base.default_value
    texcoord = int(blur["diffuseNormalTextures"][0].get("texCoord", 0))
    uv_maps = uv_map_names(mat)
    for i, (info, socket) in enumerate(zip(blur["diffuseNormalTextures"], ("Normal Red", "Normal Green", "Normal Blue"))):
        image = image_node(tree, textures, info, (x - 500, y - 260 * i))
        if image is None:
            continue
        image.extension = "REPEAT"
        normal_map = tree.nodes.new("ShaderNodeNormalMap")
        normal_map.name = normal_map.label = f"BAKER diffuse normal {socket.split()[-1].lower()}"
        normal_map.space = "TANGENT"
        if texcoord < len(uv_maps):
            normal_map.uv_map = uv_maps[texcoord]
        normal_map.location = (x - 200, y - 260 * i)
        tree.links.new(image.outputs["Color"], normal_map.inputs["Color"])
        tree.links.new(normal_map.outputs["Normal"], node.inputs[socket])
    mix_in(mat, "diffuse normals", node.outputs["Shader"], (x + 550, y))


def lookup_uv_group(name: str):
    """(N.L, value) -> (u, v): u = (N.L - lo_u) / (hi_u - lo_u), v = (value - lo_v) / (hi_v - lo_v), clamped, as
    baker_skin_lut_uv computes them; the output's y is 1 - v (Blender counts image rows from the bottom)."""
    group, io = new_group(name, [
        ("Light Direction", "NodeSocketVector", (0.0, 0.0, 1.0)), ("Value", "NodeSocketFloat", 0.0),
        ("U Min", "NodeSocketFloat", -1.0), ("U Max", "NodeSocketFloat", 1.0),
        ("V Min", "NodeSocketFloat", 0.0), ("V Max", "NodeSocketFloat", 1.0)],
        [("Vector", "NodeSocketVector"), ("NdotL", "NodeSocketFloat")])
    if io is None:
        return group
    tree, (gin, gout) = group, io
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    normalize = tree.nodes.new("ShaderNodeVectorMath")
    normalize.operation = "NORMALIZE"
    tree.links.new(gin.outputs["Light Direction"], normalize.inputs[0])
    dot = tree.nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    tree.links.new(geometry.outputs["Normal"], dot.inputs[0])
    tree.links.new(normalize.outputs[0], dot.inputs[1])
    ndotl = dot.outputs["Value"]
    coords = []
    for value, lo, hi in ((ndotl, "U Min", "U Max"), (gin.outputs["Value"], "V Min", "V Max")):
        span = math_node(tree, "MAXIMUM", math_node(tree, "SUBTRACT", gin.outputs[hi], gin.outputs[lo]), 1e-9)
        t = math_node(tree, "DIVIDE", math_node(tree, "SUBTRACT", value, gin.outputs[lo]), span)
        node = tree.nodes.new("ShaderNodeClamp")
        tree.links.new(t, node.inputs["Value"])
        coords.append(node.outputs[0])
    combine = tree.nodes.new("ShaderNodeCombineXYZ")
    tree.links.new(coords[0], combine.inputs[0])
    # glTF images have row 0 at the top, Blender's image coordinates start at the bottom row
    tree.links.new(math_node(tree, "SUBTRACT", 1.0, coords[1]), combine.inputs[1])
    tree.links.new(combine.outputs[0], gout.inputs["Vector"])
    tree.links.new(ndotl, gout.inputs["NdotL"])
    return group


def output_and_surface(mat):
    tree = mat.node_tree
    output = next((n for n in tree.nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output), None) or \
        next((n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"), None)
    if output is None:
        output = tree.nodes.new("ShaderNodeOutputMaterial")
    links = output.inputs["Surface"].links
    return output, (links[0].from_socket if links else None)


def mix_in(mat, label: str, shader_socket, location) -> object:
    """Put ``shader_socket`` after the current surface through a Mix Shader with factor 0 (look unchanged)."""
    tree = mat.node_tree
    output, surface = output_and_surface(mat)
    mix = tree.nodes.new("ShaderNodeMixShader")
    mix.name = mix.label = MIX_PREFIX + label
    mix.inputs["Fac"].default_value = 0.0
    mix.location = location
    if surface is not None:
        tree.links.new(surface, mix.inputs[1])
    tree.links.new(shader_socket, mix.inputs[2])
    tree.links.new(mix.outputs[0], output.inputs["Surface"])
    output.location = (location[0] + 250, location[1])
    return mix


def attribute_x(tree, name: str, location):
    attribute = tree.nodes.new("ShaderNodeAttribute")
    attribute.attribute_type = "GEOMETRY"
    attribute.attribute_name = name
    attribute.location = location
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    separate.location = (location[0] + 180, location[1])
    tree.links.new(attribute.outputs["Vector"], separate.inputs[0])
    return separate.outputs["X"]


def image_node(tree, textures: dict, info, location):
    if not isinstance(info, dict) or str(info.get("index")) not in textures:
        return None
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.get(textures[str(info["index"])]["blender_image"])
    node.extension = "EXTEND"
    node.location = location
    return node


CAUSTICS_ADD = "BAKER caustics add"


def caustics_coordinates_group():
    """World position -> (Vector: the frame's image coordinates, Fade), as baker_caustics_uv and baker_caustics_fade.
    Blender's (x, y, z) is glTF's (x, -z, y)."""
    group, io = new_group("BAKER Caustics Coordinates", [
        ("Projection Direction", "NodeSocketVector", (0.0, -1.0, 0.0)), ("Water Level", "NodeSocketFloat", 0.0),
        ("Depth", "NodeSocketFloat", 1.0), ("Tile Size", "NodeSocketFloat", 1.0),
        ("Fade Distance", "NodeSocketFloat", 1.0)],
        [("Vector", "NodeSocketVector"), ("Fade", "NodeSocketFloat")])
    if io is None:
        return group
    tree, (gin, gout) = group, io
    position = tree.nodes.new("ShaderNodeNewGeometry").outputs["Position"]
    world = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(position, world.inputs[0])
    direction = tree.nodes.new("ShaderNodeSeparateXYZ")  # glTF axes, as the extension writes it
    tree.links.new(gin.outputs["Projection Direction"], direction.inputs[0])
    # point depth d = waterLevel - y (glTF y = Blender z); moved along the direction by k = (depth - d) / dir.y
    point_depth = math_node(tree, "SUBTRACT", gin.outputs["Water Level"], world.outputs["Z"])
    k = math_node(tree, "DIVIDE", math_node(tree, "SUBTRACT", gin.outputs["Depth"], point_depth),
                  direction.outputs["Y"])
    # glTF uv = (Q.x, -Q.z) / tile with Q = P - dir k; Blender's image rows start at the bottom (v -> -v, the same
    # texel of a repeating frame), so the Blender vector is (Q.x, Q.z) / tile = (x - dx k, -y_b - dz k) / tile
    u = math_node(tree, "SUBTRACT", world.outputs["X"], math_node(tree, "MULTIPLY", direction.outputs["X"], k))
    v = math_node(tree, "SUBTRACT", math_node(tree, "MULTIPLY", world.outputs["Y"], -1.0),
                  math_node(tree, "MULTIPLY", direction.outputs["Z"], k))
    combine = tree.nodes.new("ShaderNodeCombineXYZ")
    tree.links.new(math_node(tree, "DIVIDE", u, gin.outputs["Tile Size"]), combine.inputs[0])
    tree.links.new(math_node(tree, "DIVIDE", v, gin.outputs["Tile Size"]), combine.inputs[1])
    tree.links.new(combine.outputs[0], gout.inputs["Vector"])
    # baker_caustics_fade: 1 - |d - depth| / fadeDistance clamped to 0..1, and 0 above the water
    off = math_node(tree, "ABSOLUTE", math_node(tree, "SUBTRACT", point_depth, gin.outputs["Depth"]))
    ramp = math_node(tree, "SUBTRACT", 1.0, math_node(tree, "DIVIDE", off, math_node(
        tree, "MAXIMUM", gin.outputs["Fade Distance"], 1e-6)))
    clamp = tree.nodes.new("ShaderNodeClamp")
    tree.links.new(ramp, clamp.inputs["Value"])
    fade = math_node(tree, "MULTIPLY", clamp.outputs[0], math_node(tree, "GREATER_THAN", point_depth, 0.0))
    tree.links.new(fade, gout.inputs["Fade"])
    return group


def caustics_group():
    """The frame's colour -> (Irradiance E = colour x Intensity Scale, Shader: emission Sunlit x (E - 1) x Strength x
    Fade), as baker_caustics_irradiance and baker_caustics_apply."""
    group, io = new_group("BAKER Caustics", [
        ("Color", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0)), ("Fade", "NodeSocketFloat", 1.0),
        ("Sunlit", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0)), ("Intensity Scale", "NodeSocketFloat", 1.0),
        ("Strength", "NodeSocketFloat", 1.0)],
        [("Irradiance", "NodeSocketColor"), ("Shader", "NodeSocketShader")])
    if io is None:
        return group
    tree, (gin, gout) = group, io
    irradiance = vector_scale(tree, gin.outputs["Color"], gin.outputs["Intensity Scale"])
    tree.links.new(irradiance, gout.inputs["Irradiance"])
    excess = tree.nodes.new("ShaderNodeVectorMath")
    excess.operation = "SUBTRACT"
    tree.links.new(irradiance, excess.inputs[0])
    excess.inputs[1].default_value = (1.0, 1.0, 1.0)
    weighted = vector_scale(tree, excess.outputs[0], math_node(tree, "MULTIPLY", gin.outputs["Strength"],
                                                               gin.outputs["Fade"]))
    sunlit = tree.nodes.new("ShaderNodeVectorMath")
    sunlit.operation = "MULTIPLY"
    tree.links.new(weighted, sunlit.inputs[0])
    tree.links.new(gin.outputs["Sunlit"], sunlit.inputs[1])
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(sunlit.outputs[0], emission.inputs["Color"])
    tree.links.new(emission.outputs[0], gout.inputs["Shader"])
    return group


def add_caustics(mat, caustics: dict, textures: dict, location) -> None:
    """The first frame through ``BAKER Caustics Coordinates`` (world position -> image coordinates, fade) and
    ``BAKER Caustics`` (irradiance, emission), added to the material's surface (Add Shader). Sunlit is the base
    colour (the Principled BSDF's, linked or set): the sun's Lambert light on it, for a sun of strength 1."""
    tree = mat.node_tree
    x, y = location
    coordinates = tree.nodes.new("ShaderNodeGroup")
    coordinates.node_tree = caustics_coordinates_group()
    coordinates.name = coordinates.label = "BAKER Caustics Coordinates"
    coordinates.location = (x - 600, y)
    group = tree.nodes.new("ShaderNodeGroup")
    group.node_tree = caustics_group()
    group.name = group.label = "BAKER Caustics"
    group.location = (x, y)
    for node, key, socket in ((coordinates, "waterLevel", "Water Level"), (coordinates, "depth", "Depth"),
                              (coordinates, "tileSize", "Tile Size"), (coordinates, "fadeDistance", "Fade Distance"),
                              (group, "intensityScale", "Intensity Scale"), (group, "strength", "Strength")):
        if key in caustics:
            node.inputs[socket].default_value = float(caustics[key])
    coordinates.inputs["Projection Direction"].default_value = [
        float(c) for c in caustics.get("projectionDirection", (0.0, -1.0, 0.0))][:3]
    tree.links.new(coordinates.outputs["Fade"], group.inputs["Fade"])
    frames = caustics.get("frameTextures") or []
    image = image_node(tree, textures, frames[0] if frames else None, (x - 300, y))
    if image is not None:
        image.extension = "REPEAT"  # the frames tile
        tree.links.new(coordinates.outputs["Vector"], image.inputs["Vector"])
        tree.links.new(image.outputs["Color"], group.inputs["Color"])
    principled = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if principled is not None:
        base = principled.inputs["Base Color"]
        if base.links:
            tree.links.new(base.links[0].from_socket, group.inputs["Sunlit"])
        else:
            group.inputs["Sunlit"].default_value = tuple(base.default_value)
    output, surface = output_and_surface(mat)
    add = tree.nodes.new("ShaderNodeAddShader")
    add.name = add.label = CAUSTICS_ADD
    add.location = (x + 250, y)
    if surface is not None:
        tree.links.new(surface, add.inputs[0])
    tree.links.new(group.outputs["Shader"], add.inputs[1])
    tree.links.new(add.outputs[0], output.inputs["Surface"])
    output.location = (x + 500, y)


CARDS_TANGENT = "BAKER Hair Cards Tangent"


def add_hair_cards(mat, cards: dict, textures: dict, location) -> None:
    """BAKER_hair_cards (baker_hair_cards.glsl, RTR4 14.7.1): the flow texture decoded in the card's frame (UV
    tangent T, N, bitangent cross(T, N): root -> tip, as baker_hair_cards_flow with TANGENT.w = -1) into the
    Principled BSDF's Tangent, with anisotropy, so its highlight runs across the strands (Kajiya-Kay's look); the
    data texture's strand random value varies the roughness per strand. The stock importer's alpha clip stays."""
    tree = mat.node_tree
    principled = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    x, y = location
    flow = image_node(tree, textures, cards.get("flowTexture"), (x - 1400, y))
    data = image_node(tree, textures, cards.get("dataTexture"), (x - 1400, y - 300))
    if principled is None or flow is None:
        return
    coords = tree.nodes.new("ShaderNodeUVMap")
    coords.location = (x - 1650, y)
    for image in (flow, data):
        if image is not None:
            tree.links.new(coords.outputs["UV"], image.inputs["Vector"])
    decode = tree.nodes.new("ShaderNodeVectorMath")  # 0..1 texel -> -1..1
    decode.operation = "MULTIPLY_ADD"
    decode.location = (x - 1150, y)
    tree.links.new(flow.outputs["Color"], decode.inputs[0])
    decode.inputs[1].default_value = (2.0, 2.0, 2.0)
    decode.inputs[2].default_value = (-1.0, -1.0, -1.0)
    split = tree.nodes.new("ShaderNodeSeparateXYZ")
    split.location = (x - 950, y)
    tree.links.new(decode.outputs["Vector"], split.inputs[0])
    tangent = tree.nodes.new("ShaderNodeTangent")
    tangent.direction_type = "UV_MAP"
    tangent.location = (x - 1150, y - 250)
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    geometry.location = (x - 1150, y - 450)
    bitangent = tree.nodes.new("ShaderNodeVectorMath")
    bitangent.operation = "CROSS_PRODUCT"
    bitangent.location = (x - 950, y - 300)
    tree.links.new(tangent.outputs["Tangent"], bitangent.inputs[0])
    tree.links.new(geometry.outputs["Normal"], bitangent.inputs[1])
    total = None
    for i, (component, axis) in enumerate((("X", tangent.outputs["Tangent"]), ("Y", bitangent.outputs["Vector"]),
                                           ("Z", geometry.outputs["Normal"]))):
        term = tree.nodes.new("ShaderNodeVectorMath")
        term.operation = "SCALE"
        term.location = (x - 750, y - 150 * i)
        tree.links.new(axis, term.inputs[0])
        tree.links.new(split.outputs[component], term.inputs["Scale"])
        if total is None:
            total = term.outputs["Vector"]
            continue
        add = tree.nodes.new("ShaderNodeVectorMath")
        add.operation = "ADD"
        add.location = (x - 550, y - 150 * i)
        tree.links.new(total, add.inputs[0])
        tree.links.new(term.outputs["Vector"], add.inputs[1])
        total = add.outputs["Vector"]
    unit = tree.nodes.new("ShaderNodeVectorMath")
    unit.operation = "NORMALIZE"
    unit.name = unit.label = CARDS_TANGENT
    unit.location = (x - 350, y)
    tree.links.new(total, unit.inputs[0])
    tree.links.new(unit.outputs["Vector"], principled.inputs["Tangent"])
    principled.inputs["Anisotropic"].default_value = 0.8
    if data is not None:
        channels = tree.nodes.new("ShaderNodeSeparateColor")
        channels.location = (x - 1150, y - 650)
        tree.links.new(data.outputs["Color"], channels.inputs["Color"])
        roughness = tree.nodes.new("ShaderNodeMapRange")
        roughness.location = (x - 950, y - 650)
        roughness.inputs["To Min"].default_value = 0.4
        roughness.inputs["To Max"].default_value = 0.6
        tree.links.new(channels.outputs["Blue"], roughness.inputs["Value"])
        tree.links.new(roughness.outputs["Result"], principled.inputs["Roughness"])


def add_material_groups(mat, exts: dict, textures: dict) -> None:
    if not mat.use_nodes:
        mat.use_nodes = True
    tree = mat.node_tree
    x, y = 600, -400
    thickness = exts.get("BAKER_thickness")
    if isinstance(thickness, dict):
        node = tree.nodes.new("ShaderNodeGroup")
        node.node_tree = translucency_group()
        node.name = node.label = "BAKER Translucency"
        node.location = (x, y)
        if thickness.get("attribute"):
            tree.links.new(attribute_x(tree, thickness["attribute"], (x - 400, y)), node.inputs["Thickness"])
        color = list(thickness.get("subsurfaceColor", (1.0, 1.0, 1.0)))[:3]
        node.inputs["Subsurface Color"].default_value = (*color, 1.0)
        for key, socket in (("attenuationDistance", "Attenuation Distance"), ("scale", "Scale"), ("ambient", "Ambient")):
            if key in thickness:
                node.inputs[socket].default_value = float(thickness[key])
        mix_in(mat, "translucency", node.outputs["Shader"], (x + 250, y))
        y -= 400
    for name, label, texture_key, value_source in (
            ("BAKER_skin_lut", "Skin LUT", "lutTexture", "curvature"),
            ("BAKER_toon_ramp", "Toon Ramp", "rampTexture", None)):
        ext = exts.get(name)
        if not isinstance(ext, dict):
            continue
        uv = tree.nodes.new("ShaderNodeGroup")
        uv.node_tree = lookup_uv_group("BAKER LUT Coordinates")
        uv.name = uv.label = f"BAKER {label}"
        uv.location = (x - 200, y)
        if value_source == "curvature":
            lo, hi = ext.get("ndotlRange", (-1.0, 1.0))
            uv.inputs["U Min"].default_value, uv.inputs["U Max"].default_value = float(lo), float(hi)
            lo, hi = ext.get("curvatureRange", (0.0, 1.0))
            uv.inputs["V Min"].default_value, uv.inputs["V Max"].default_value = float(lo), float(hi)
            scaled = math_node(tree, "MULTIPLY", attribute_x(tree, ext.get("curvatureAttribute", "_CURVATURE"),
                                                             (x - 700, y)), float(ext.get("curvatureScale", 1.0)))
            tree.links.new(scaled, uv.inputs["Value"])
        image = image_node(tree, textures, ext.get(texture_key), (x, y))
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.location = (x + 300, y)
        if image is not None:
            tree.links.new(uv.outputs["Vector"], image.inputs["Vector"])
            tree.links.new(image.outputs["Color"], emission.inputs["Color"])
        mix_in(mat, label.lower(), emission.outputs[0], (x + 500, y))
        y -= 400
    fur = exts.get("BAKER_fur")
    if isinstance(fur, dict) and fur.get("shellTextures"):
        # the innermost shell (colour + coverage) tiled over TEXCOORD_0, where the fur starts; shells above it and
        # the fins are drawn by the runtime (baker_fur.glsl), not by this node setup
        coords = tree.nodes.new("ShaderNodeTexCoord")
        coords.location = (x - 600, y)
        tiled = vector_scale(tree, coords.outputs["UV"], float(fur.get("tiling", 1.0)))
        image = image_node(tree, textures, fur["shellTextures"][0], (x - 200, y))
        shell = tree.nodes.new("ShaderNodeMixShader")
        shell.name = shell.label = "BAKER Fur Shell"
        shell.location = (x + 200, y)
        transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
        emission = tree.nodes.new("ShaderNodeEmission")
        tree.links.new(transparent.outputs[0], shell.inputs[1])
        tree.links.new(emission.outputs[0], shell.inputs[2])
        if image is not None:
            image.extension = "REPEAT"
            tree.links.new(tiled, image.inputs["Vector"])
            tree.links.new(image.outputs["Color"], emission.inputs["Color"])
            tree.links.new(image.outputs["Alpha"], shell.inputs["Fac"])
        mix_in(mat, "fur", shell.outputs[0], (x + 500, y))
        y -= 400
    tam = exts.get("BAKER_tonal_art_map")
    if isinstance(tam, dict) and tam.get("levels"):
        uv = tree.nodes.new("ShaderNodeGroup")
        uv.node_tree = lookup_uv_group("BAKER LUT Coordinates")
        uv.name = uv.label = "BAKER Hatching"
        uv.location = (x - 200, y)
        tones = [float(t) for t in tam.get("tones", [])]
        images = [image_node(tree, textures, info, (x, y - 260 * i))
                  for i, info in enumerate(tam["levels"][0].get("textures", []))]
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.location = (x + 300, y)
        first = next((im for im in images if im is not None), None)
        if first is not None:
            # the UV map of TEXCOORD_<texCoord> by name (baker's stroke parameterization is a set of its own), in
            # tile units: uv * scale / levels[0].size, as baker_tam_coord
            coords = tree.nodes.new("ShaderNodeUVMap")
            coords.name = coords.label = "BAKER Hatching UV"
            coords.location = (x - 400, y - 200)
            uv_maps = uv_map_names(mat)
            texcoord = int(tam.get("texCoord", 0))
            if texcoord < len(uv_maps):
                coords.uv_map = uv_maps[texcoord]
            size = float(tam["levels"][0].get("size", 0) or 0)
            tile = float(tam.get("scale", size)) / size if size > 0 else 1.0
            vector = coords.outputs["UV"] if tile == 1.0 else vector_scale(tree, coords.outputs["UV"], tile)
            for im in images:
                if im is not None:
                    im.extension = "REPEAT"
                    tree.links.new(vector, im.inputs["Vector"])
            tree.links.new(first.outputs["Color"], emission.inputs["Color"])
        mix_in(mat, "hatching", emission.outputs[0], (x + 500, y))
        mat["baker_tam_tones"] = tones
        y -= 400
    blur = exts.get("BAKER_normal_blur")
    if isinstance(blur, dict) and len(blur.get("diffuseNormalTextures") or []) == 3:
        add_diffuse_normals(mat, blur, textures, (x, y))
        y -= 800
    caustics = exts.get("BAKER_caustics")
    if isinstance(caustics, dict):
        add_caustics(mat, caustics, textures, (x, y))
        y -= 400
    cards = exts.get("BAKER_hair_cards")
    if isinstance(cards, dict):
        add_hair_cards(mat, cards, textures, (x, y))
