"""Every friction law of the project and the one route to them (`[lubrication] viscous_model`,
`shear_strength`, `lubrication_method`, `oil_level_mm`; docs/cli.md). The laws, one effect per
file (the one place they are listed):

  palmgren     Palmgren's load and viscous terms (and the GB/T 28878.2 form)
  skf2004      SKF four-component model (rolling with inlet shear heating and replenishment
               reductions, sliding with boundary / full-film weighting, oil-bath drag)
  ehl_rolling  hydrodynamic rolling resistance per ball-raceway contact (EHL), located heat;
               an unloaded contact rolls under the ball's centrifugal force; each contact's
               spin sliding (full-slip pivoting moment, traction bounded by SKF's mu_EHL)
  starved      Palmgren's viscous term weakened by a finite oil quantity (starved EHL inlet)
  solid_film   pressure-dependent interfacial shear strength of a solid film (MoS2)

The glue: `options` (the law's typed options), `pair` (the route: one bearing's contacts
through the chosen law, `bearing_friction`, and a pair's sum with the heat by location,
`pair_torque`), `ranges` (where a law leaves its source's range: one warning line per law).
`simulate`, `bearing`, the transient route, the thermal speeds and the diagnosis's friction rungs
take this route.

Units as the rest of `analytic`: N, mm, s, MPa; rpm and mm^2/s where the name says so.
"""
