"""Geotechnical engineering checks beside the two-fluid model.

- :mod:`.simplified` — liquefaction triggering by the simplified procedure
  (Idriss & Boulanger 2008, 2014): r_d, MSF, K_σ, CRR from (N1)60cs, CSR, FS;
- :mod:`.settlement` — post-liquefaction volumetric strain (Ishihara & Yoshimine 1992,
  as fitted by Idriss & Boulanger 2008);
- :mod:`.profile` — both over a layered profile (:func:`simplified_procedure`);
- :mod:`.spectra` — elastic response spectra (Nigam & Jennings 1969);
- :mod:`.correlations` — Dr [%] from (N1)60cs and q_c1Ncs, the CPT route of B&I (2014), the
  CSR–N slope b from MSF_max, residual strength, K_α, Seed–Booker r_u (docs/dynamic-curves.md).
- :mod:`.lateral_spread` — lateral spreading on gentle slopes: Zhang et al. (2004), Youd et al.
  (2002), a one-way Newmark block on the residual strength (docs/lateral-spreading.md).

All are pure NumPy functions; see ``docs/simplified.md``.
"""
from .profile import SimplifiedResult, simplified_procedure
from .spectra import amplification, response_spectrum, sdof_history, standard_periods

__all__ = ["SimplifiedResult", "simplified_procedure", "response_spectrum", "sdof_history",
           "amplification", "standard_periods"]
