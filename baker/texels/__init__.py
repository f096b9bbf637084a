"""The texel layer: what every texture bake shares, between the mesh geometry (:mod:`baker.geometry`) and the
techniques.

- :mod:`.texture_space`  UV layout (xatlas unwrap), texel -> surface samples (rasterized UVs), dilation, sizes from
                         texel density
- :mod:`.targets`        per material: the UV set, size and texels a texture bake writes (an unwrap when needed)
- :mod:`.sets`           every material's texels as one stream of surface samples, windows, images back
- :mod:`.tangents`       tangent frames of a UV layout (UV Jacobians, MikkTSpace-like tangents)
- :mod:`.alpha_mips`     coverage-preserving alpha mip chains (Castaño 2010) as KTX2 in an accessor
- :mod:`.color`          colour transfer functions (sRGB), written once
"""
