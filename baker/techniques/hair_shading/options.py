"""Options of the hair fibre tables (``baker hair-lut --hair-*``): one frozen dataclass, pbrt's parameter names."""
from __future__ import annotations

from dataclasses import dataclass

from baker.options import opt


@dataclass(frozen=True)
class HairShadingOptions:
    """The fibre model's parameters (Chiang et al. 2016, pbrt's HairBxDF) and the tables' sizes."""

    beta_m: float = opt(0.3, "longitudinal roughness (0..1; Chiang's variance map; the M table is baked for it)",
                        min=0.05, max=1.0)
    beta_n: float = opt(0.3, "azimuthal roughness (0..1; Chiang's logistic scale map; the N table is baked for it)",
                        min=0.05, max=1.0)
    eta: float = opt(1.55, "index of refraction of the fibre (the N table is baked for it)", min=1.01, max=3.0)
    alpha: float = opt(2.0, "cuticle tilt, degrees (applied at lookup; recorded in the JSON as the default)",
                       min=-10.0, max=10.0)
    eumelanin: float = opt(1.3, "eumelanin concentration (d'Eon et al. 2011; 0.3 blond, 1.3 brown, 8 black; "
                                "absorption is a table axis: recorded in the JSON as the default)", min=0.0, max=50.0)
    pheomelanin: float = opt(0.0, "pheomelanin concentration (red hair; recorded in the JSON as the default)",
                             min=0.0, max=50.0)
    m_size: int = opt(128, "M table texels along theta_i and theta_o", min=8, max=2048)
    phi_size: int = opt(64, "N table texels along |phi| (0..pi)", min=8, max=2048)
    theta_size: int = opt(32, "N table texels along |theta_o| (0..pi/2) per absorption slice", min=4, max=1024)
    slices: int = opt(16, "N table slices along the absorption axis x = 1 - exp(-sigma_a / 2)", min=2, max=256)
    offsets: int = opt(64, "Gauss-Legendre nodes over the fibre offset h (the far-field average)", min=4, max=1024)


@dataclass(frozen=True)
class HairMaterialOptions:
    """The hair material of ``baker hair``, ``baker guides`` and ``baker cards`` (``BAKER_hair_shading`` on the
    material of every hair primitive: Chiang et al. 2016's fibre model, its tables embedded once per file; strands
    also get the rest-pose occlusion and fibre counts)."""

    eumelanin: float = opt(1.3, "eumelanin concentration (d'Eon et al. 2011; 0.3 blond, 1.3 brown, 8 black)",
                           min=0.0, max=50.0)
    pheomelanin: float = opt(0.0, "pheomelanin concentration (red hair)", min=0.0, max=50.0)
    color: str | None = opt(None, "hair colour as linear r,g,b in (0, 1): the absorption from Chiang et al. 2016's "
                                  "inversion instead of melanin (default: from the melanin)")
    roughness: tuple = opt((0.3, 0.3), "longitudinal,azimuthal roughness beta_m,beta_n (0.05..1)", min=0.05, max=1.0)
    tilt: float = opt(2.0, "cuticle tilt alpha, degrees", min=-10.0, max=10.0)
    eta: float = opt(1.55, "index of refraction of the fibre", min=1.01, max=3.0)
    melanin_variation: float = opt(0.2, "strands only: per-strand melanin varies by this factor (eumelanin and "
                                        "pheomelanin x exp(variation x normal), the _HAIR_MELANIN attribute); 0: "
                                        "none", min=0.0, max=2.0)
    occlusion_rays: int = opt(16, "strands only: rays per strand vertex for _HAIR_OCCLUSION and the fibre counts "
                                  "(0: neither)", min=0, max=1024)

    def __post_init__(self):
        if self.color is not None:
            rgb = parse_color(self.color)
            object.__setattr__(self, "color", ",".join(f"{c:g}" for c in rgb))

    @property
    def rgb(self) -> tuple | None:
        return None if self.color is None else parse_color(self.color)


def parse_color(text) -> tuple:
    """(r, g, b) of ``--hair-color`` ('r,g,b' or three numbers), each in (0, 1); ValueError names the problem."""
    parts = text.split(",") if isinstance(text, str) else list(text)
    try:
        rgb = tuple(float(p) for p in parts)
    except (TypeError, ValueError):
        raise ValueError(f"option 'color' expects r,g,b, got {text!r}") from None
    if len(rgb) != 3 or not all(0.0 < c < 1.0 for c in rgb):
        raise ValueError(f"option 'color' expects three linear values in (0, 1), got {text!r}")
    return rgb
