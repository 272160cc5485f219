"""The stages of the model's one route (`studies.model.pipeline.Pipeline.run`), top-down:

1. `fe`       conditions -> part thermal strains, fit interferences, rotor speed -> the FE answer
              (`FEState`: fit pressures, groove-centre shifts, raceway displacements), through
              the condensed superposition or direct solves; `grooves` turns probed
              displacements into groove-centre shifts;
2. `lame`     the closed-form (Lamé) neighbours of the FE fit values (`LameNeighbours`);
3. `bearing`  the pair equilibrium from the shifts (`analytic.bearing.PairState`) and what is
              read off it (`PairSummary`: pair contact angle, land margins, static safety);
4. `torque`   friction torque of the pair (`analytic.friction.pair.TorqueComponents`);
then the checks (`studies.model.checks.Checks`). Each stage is a function or a small class from
typed inputs to a typed output; `studies.model.result.SimulationResult` holds them all and
`studies.model.columns.to_columns` is the one place they become named columns.
"""
