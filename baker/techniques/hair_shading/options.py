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
