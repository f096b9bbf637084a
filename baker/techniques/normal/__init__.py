"""The high mesh's normals baked onto the low mesh's UVs through a cage: a tangent-space normal map in the frame of
the low's TANGENT (the frame glTF viewers decode with), or an object-space map (``baker bake LOW --from HIGH``)."""
from baker.technique import Technique
from baker.techniques.normal.options import NormalOptions

TECHNIQUE = Technique(
    name='normal',
    summary='normal map of a high-poly source on the low mesh\'s UVs (--from HIGH; normalTexture + TANGENT)',
    options=NormalOptions,
    run="baker.techniques.normal.step:run",
    transfers=True,
)
