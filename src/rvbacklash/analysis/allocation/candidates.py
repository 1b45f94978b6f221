"""Candidates (one grade per part group) shared by the MILP and the Monte-Carlo search: their
single-group moves and the uniform grades, their names, and the result pieces built from them
(the binding constraint, the groups table, the non-dominated front).
"""

from __future__ import annotations

import math
from typing import Sequence

from rvbacklash.analysis.allocation.results import Binding, FrontPoint, GroupGrade
from rvbacklash.analysis.grade_choices import GradeChoices
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.problem import Problem


def neighbour_grades(ch: GradeChoices, grades: tuple[int, ...], step: int) -> list[tuple[int, ...]]:
    """Candidates that move one group one grade coarser (step +1) or finer (step -1)."""
    out = []
    for j, c in enumerate(ch.groups):
        k = c.grades.index(grades[j]) + step
        if 0 <= k < len(c.grades):
            out.append(grades[:j] + (c.grades[k],) + grades[j + 1:])
    return out


def swap_grades(ch: GradeChoices, grades: tuple[int, ...]) -> list[tuple[int, ...]]:
    """Coarsen one group and tighten another, when that is cheaper."""
    out = []
    for a in neighbour_grades(ch, grades, +1):
        for b in neighbour_grades(ch, a, -1):
            if b != grades and sum(x != y for x, y in zip(b, grades)) == 2 and ch.cost(b) < ch.cost(grades):
                out.append(b)
    return out


def uniform_grades(choices: GradeChoices) -> list[tuple[int, tuple[int, ...]]]:
    common = set(choices.groups[0].grades).intersection(*(c.grades for c in choices.groups[1:]))
    return [(g, tuple(g for _ in choices.groups)) for g in sorted(common)]


def named_grades(choices: GradeChoices, grades: Sequence[int]) -> dict[str, int]:
    return {c.name: int(g) for c, g in zip(choices.groups, grades)}


def design_description(problem: Problem, label: str) -> str:
    base = problem.design.description
    return (base + " | " if base else "") + label


def binding_constraint(label: str, value: Proportion, target: float, choices: GradeChoices,
             grades: Sequence[int]) -> Binding:
    finest = tuple(c.name for c, g in zip(choices.groups, grades) if g == c.grades[0])
    return Binding(label, value.fraction, value.ci95_low, target, value.ci95_low - target, finest)


def groups_table(choices: GradeChoices, grades: Sequence[int]) -> tuple[GroupGrade, ...]:
    return tuple(GroupGrade(c.name, c.group.grade_table, tuple(c.group.factors), c.current_grade, int(g),
                            c.current_cost, c.cost_of(g), c.grades[0], c.grades[-1], c.group.description)
                 for c, g in zip(choices.groups, grades))


def pareto_front(points: list[FrontPoint]) -> tuple[FrontPoint, ...]:
    """Non-dominated points (cheaper or higher yield than every other), cheapest first; one point
    per distinct design."""
    unique: dict[tuple, FrontPoint] = {}
    for p in points:
        key = tuple(sorted(p.grades.items()))
        if key not in unique or p.chosen:
            unique[key] = p
    pts = sorted(unique.values(), key=lambda p: (p.cost, -p.yield_.fraction))
    out: list[FrontPoint] = []
    best = -math.inf
    for p in pts:
        if p.yield_.fraction > best + 1e-15:
            out.append(p)
            best = p.yield_.fraction
    return tuple(out)
