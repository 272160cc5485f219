"""Friction models beyond Palmgren's viscous term, one effect per file (`[lubrication]
viscous_model`, `shear_strength`; docs/cli.md):

  skf2004      SKF four-component model (rolling with inlet shear heating and replenishment
               reductions, sliding with boundary / full-film weighting, drag)
  ehl_rolling  hydrodynamic rolling resistance per ball-raceway contact (EHL), located heat
  starved      Palmgren's viscous term weakened by a finite oil quantity (starved EHL inlet)
  solid_film   pressure-dependent interfacial shear strength of a solid film (MoS2)

Units as the rest of `analytic`: N, mm, s, MPa; rpm and mm^2/s where the name says so.
"""
