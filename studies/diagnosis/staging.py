"""Staged rungs of the model-form ladder: the thermal kin's model form (`thermal_transient_fe`,
a member of `generalised.THERMAL_KIN` that is a ladder form) is what the diagnosis proposes
where the lumped thermal forms (the kin's listed effects, `thermal_lag` and `radial_gradient`,
and their generalised forms) leave structure, not a rival fitted beside them on every dataset
(docs/diagnosis.md, "The model-form ladder").

A pass (`engine.one_pass`) whose residual indicates a staged rung (`ladder.Indication`) runs in
two stages on the same calibration:

1. every other candidate is screened, fitted, validated, decided and generalised as in any
   pass; the staged rung is held (`PENDING`), counted in Holm's number of tests (a union bound
   over the two stages);
2. unless a rule below gives a reason not to (then the rung is `not_applicable` with that
   reason in diagnosis.json), the rung is screened and fitted, the first stage's screening and
   fits reused, and the pass is validated, decided and generalised again with it (Holm over
   every fitted candidate).

The rules, one small function each:

- `held`: a lumped thermal form accepted already (a later pass of the forward selection) makes
  the rung a second thermal history of the same parts: not applicable;
- `lumped_explains`: the first stage is explained by a lumped thermal form (listed or
  generalised), or ambiguous with one among the tied, and that form leaves no structure under
  the noise re-estimated from its own residual (`selection.cause_explains_at_its_noise`: a
  lag's misfit taken for noise hides what the lag leaves);
- `lumped_tie`: in the second stage the rung ties with lumped thermal forms only (ambiguous, or
  unexplained with them as rivals): the lumped form, cheaper and listed, is the claim; the
  first stage's pass stands (the further-cause search goes on from it) and the rung's record
  says why.
"""
from __future__ import annotations

from dataclasses import replace

from studies.diagnosis.generalised import THERMAL_KIN
from studies.diagnosis.ladder import is_form
from studies.diagnosis.problem import Problem
from studies.diagnosis.selection import cause_explains_at_its_noise

#: the reason a staged rung carries while the first stage runs (never in a result)
PENDING = "held until the lumped thermal forms are judged"


def is_staged(e) -> bool:
    """True for a ladder form of the thermal kin (screened only in the second stage)."""
    return is_form(e) and e.name in THERMAL_KIN


def is_lumped(pb: Problem, name: str | None) -> bool:
    """True for a listed effect of the thermal kin (a generalised form counts as its family)
    among the problem's candidates or accepted causes."""
    effects = {e.name: e for e in pb.candidates} | {a.effect.name: a.effect for a in pb.base}
    e = effects.get(name)
    fam = getattr(e, "family", None) or name
    return fam in THERMAL_KIN and e is not None and not is_form(e)


def held(pb: Problem) -> dict[str, str]:
    """{name: reason} of the staged rungs among the candidates: PENDING, or why the rung is
    not tried at all in this pass (a lumped thermal form is an accepted cause already)."""
    accepted = [a.effect.name for a in pb.base if is_lumped(pb, a.effect.name)]
    why = (f"a lumped thermal form is an accepted cause already ({', '.join(accepted)}): the "
           "rung would be a second thermal history of the same parts" if accepted else PENDING)
    return {e.name: why for e in pb.candidates if is_staged(e)}


def lumped_explains(p) -> str | None:
    """The reason the staged rung is not tried after the first stage's pass `p`
    (`engine.Pass`), or None: a lumped thermal form explains the data (module docstring)."""
    d = p.decision
    names = ([d.cause] if d.verdict == "explained" else
             [d.best, *d.rivals] if d.verdict == "ambiguous" else [])
    for n in names:
        if not is_lumped(p.pb, n):
            continue
        as_cause = p if n == d.cause else replace(p, decision=replace(d, cause=n),
                                                  chosen=None)
        if cause_explains_at_its_noise(as_cause):
            what = p.chosen.entry.text if p.chosen is not None and n == d.cause else n
            return f"a lumped lag leaves no structure ({what})"
    return None


def lumped_tie(p, staged: list[str]) -> str | None:
    """Why the second stage's pass `p` gives way to the first stage's, or None: its best and
    rivals are the staged rung and lumped thermal forms only (module docstring)."""
    d = p.decision
    if not d.rivals or d.verdict not in ("ambiguous", "unexplained"):
        return None
    tied = {d.best, *d.rivals}
    others = sorted(tied - set(staged))
    if not tied & set(staged) or not others or not all(is_lumped(p.pb, n) for n in others):
        return None
    return (f"it fits about as well as the lumped {', '.join(others)}, the cheaper listed "
            "form, which is the claim")


def with_reasons(p, records: dict):
    """Pass `p` with the staged rungs' candidate records replaced (`records`: name ->
    Candidate)."""
    return replace(p, candidates={**p.candidates, **records})
