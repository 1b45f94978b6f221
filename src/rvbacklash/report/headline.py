"""The first screen of the report: title, lead and headline cards of the model the user chose.

Linear: the stack-up's backlash (mean, mean + 3σ, the Monte-Carlo's 99.865 % and the yield);
contact: the rigid lost motion of the exact cycloid-pin contact and the preloaded share; elastic:
what the test bench reads (lost motion, backlash, torsional rigidity) and the yield against every
spec given; transmission: the transmission error's peak-to-peak over an output revolution and the
rigid lost motion at the reference position. Every number on a card is one of ``ReportData.key_numbers()`` (marked ``data-key``)
so that the page and the JSON cannot disagree. A card with a yield appears only when its spec
was given.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rvbacklash.units import display_unit


@dataclass(frozen=True)
class Number:
    """A marked number: its key in ``key_numbers``, the value, the format and the unit shown."""

    key: str
    value: float | None
    fmt: str = ".3f"
    unit: str = ""
    scale: float = 1.0  # shown = value x scale (100 for a percentage)


@dataclass(frozen=True)
class Card:
    label: str
    number: Number
    subs: tuple = field(default_factory=tuple)  # str, or (text before, Number, text after)


MODEL_NAMES = {"linear": "linear model (Sun et al. 2014, Eq. (1)/(2))",
               "contact": "contact model (exact cycloid–pin contact, rigid parts; docs/contact.md)",
               "elastic": "elastic model (the test bench's hysteresis loop; docs/elastic.md)",
               "transmission": "transmission model (each unit of the contact model turned through one output "
                               "revolution, rigid parts; docs/transmission-error.md)"}

TITLES = {"linear": "Backlash of", "contact": "Rigid lost motion of", "elastic": "Test-bench figures of",
          "transmission": "Transmission error of"}

LEADS = {
    "linear": "lost motion at the output of an RV reducer, predicted from geometry and tolerances (model of Sun et "
              "al. 2014, Eq. (1)/(2), 21 error factors).",
    "contact": "the rigid lost motion at the output of every unit of a production run: each pin and each tooth "
               "with its own errors, the exact modified cycloid profile, the first contact decides (no load). "
               "The linear stack-up below explains where it comes from.",
    "elastic": "what the test bench will read off every unit of a production run: lost motion at ±3 % of the rated "
               "torque, backlash and torsional rigidity from the hysteresis loop (Hertz contacts of the pins, "
               "needle bearings, involute mesh, and the crankshafts, support bearings and carrier where the design "
               "gives them), and the share of units within spec. The linear stack-up below "
               "explains where the lost motion comes from.",
    "transmission": "the angular transmission error of every unit of a production run over one output revolution "
                    "(its peak-to-peak, the catalogue figure), and its rigid lost motion at the bench's reference "
                    "position (the cycloid stage plus the involute and crank stages): each pin and tooth with its "
                    "own errors, the gears' eccentricities and the crank holes' positions, the exact modified "
                    "cycloid profile, no load. The linear stack-up below explains where the lost motion comes from.",
}

LABELS = {"lost_motion": "lost motion", "backlash": "backlash", "rigidity": "torsional rigidity",
          "preload": "cycloid-stage preload", "backlash_free": "backlash of the free units",
          "transmission_error": "TE peak-to-peak", "lost_motion_max": "largest rigid lost motion"}
# what an output is called on this model's cards where the shared name would mislead
MODEL_LABELS = {("contact", "backlash"): "rigid lost motion",
                ("transmission", "backlash"): "rigid lost motion (reference position)"}


def label(model: str, name: str) -> str:
    """An output's name on the first screen of a report of ``model``."""
    return MODEL_LABELS.get((model, name), LABELS.get(name, name.replace("_", " ")))


def model_name(model: str) -> str:
    return MODEL_NAMES.get(model, f"{model} model")


def title(data) -> str:
    return TITLES.get(data.model, "Backlash of")


def lead(data) -> str:
    return LEADS.get(data.model, LEADS["linear"]).replace("±3 %", f"±{_measuring_pct(data)}")


def _measuring_pct(data) -> str:
    """The lost motion's measuring torque, as a share of the rated torque (the elastic section's)."""
    n = getattr(data.elastic, "nominal", None)
    return f"{n.measuring_torque_fraction * 100:g} %" if n is not None else "3 %"


# the short flag a card carries when its output has a warning (the warning itself is in the report's warnings)
_FLAGS = {"lost_motion": "friction ≥ the measuring torque: this is the stick band's width, not the play (warnings)"}


def _pct(key: str, value: float | None) -> Number:
    return Number(key, value, ".2f", "%", 100.0)


def _yield_cards(data, keys: dict) -> list[Card]:
    sim, cards = data.simulation, []
    for name, o in sim.outputs.items():
        key = f"simulation.{name}.yield"
        if o.yield_ is None or key not in keys:
            continue
        side = "≤" if o.spec_is_upper else "≥"
        ppm = f"; {o.ppm_out:.0f} ppm out" if o.ppm_out is not None else ""
        flag = ("⚠ " + _FLAGS.get(name, "see the warnings above"),) if o.warning else ()
        cards.append(Card(f"yield, {label(data.model, name)} {side} {o.spec_limit:g} {display_unit(o.unit)}",
                          _pct(key, keys[key]),
                          (f"95 % CI {o.yield_.ci95_low * 100:.2f} – {o.yield_.ci95_high * 100:.2f} %{ppm}",) + flag))
    if "simulation.joint_yield" in keys:
        j = sim.joint_yield
        cards.append(Card("yield, every spec at once", _pct("simulation.joint_yield", keys["simulation.joint_yield"]),
                          (f"95 % CI {j.ci95_low * 100:.2f} – {j.ci95_high * 100:.2f} %",)))
    return cards


def _linear_cards(data, keys: dict) -> list[Card]:
    out = data.simulation.output
    q = out.quantiles.at(0.99865)
    cards = [
        Card("mean backlash", Number("total.mean_arcmin", keys["total.mean_arcmin"], unit="arcmin"),
             (("σ = ", Number("total.sigma_arcmin", keys["total.sigma_arcmin"], unit="arcmin"), ""),)),
        Card("mean + 3σ (statistical)", Number("total.plus3sigma_arcmin", keys["total.plus3sigma_arcmin"],
                                               unit="arcmin"),
             (("worst case ", Number("total.worst_case_arcmin", keys["total.worst_case_arcmin"], unit="arcmin"),
               ""),)),
        Card("99.865 % of units below", Number("simulation.q99865_arcmin", keys["simulation.q99865_arcmin"],
                                               unit="arcmin"),
             (f"95 % CI {q.interval_text('.3f', ' – ', '')}",)),
    ]
    if out.yield_ is not None and "simulation.yield" in keys:
        cpk = f"; Cpk {out.cpk:.2f}" if out.cpk is not None else ""
        cards.append(Card(f"yield, backlash ≤ {out.spec_limit:g} arcmin", _pct("simulation.yield",
                                                                                keys["simulation.yield"]),
                          (f"95 % CI {out.yield_.ci95_low * 100:.2f} – {out.yield_.ci95_high * 100:.2f} %; "
                           f"{out.ppm_out:.0f} ppm out{cpk}",)))
    return cards


def _f(v: float | None, spec: str = ".3f") -> str:
    return "–" if v is None else format(v, spec)


def _model_cards(data, keys: dict) -> list[Card]:
    sim, cards = data.simulation, []
    for name in data.headline_outputs():
        o = sim.outputs.get(name)
        if o is None:
            continue
        unit = display_unit(o.unit)
        fmt = ".0f" if unit == "N·m/arcmin" else ".3f"
        lower = name == "rigidity"
        tail = "simulation.%s.q%s" % (name, "00135" if lower else "99865")
        if data.model == "elastic":
            text = {"lost_motion": f"mean lost motion (±{_measuring_pct(data)} T_R)",
                    "backlash": "mean backlash (loop width at 0 N·m)",
                    "rigidity": "mean torsional rigidity"}.get(name, f"mean {label(data.model, name)}")
        elif data.model == "transmission" and name == "transmission_error":
            text = "mean TE peak-to-peak (one output revolution)"
        else:
            text = f"mean {label(data.model, name)}"
        flag = ("⚠ " + _FLAGS.get(name, "see the warnings above"),) if o.warning else ()
        cards.append(Card(text, Number(f"simulation.{name}.mean", keys[f"simulation.{name}.mean"], fmt, unit),
                          ((f"99.865 % of units {'above' if lower else 'below'} ", Number(tail, keys[tail], fmt, unit),
                            ""),) + flag))
    if data.model == "contact" and "simulation.preload_fraction" in keys:
        cards.append(Card("units with a preloaded cycloid stage",
                          _pct("simulation.preload_fraction", keys["simulation.preload_fraction"]),
                          ("rigid interference at some pin (no play)",)))
    return cards + _yield_cards(data, keys)


def cards(data) -> list[Card]:
    """The headline cards of the chosen model."""
    keys = data.key_numbers()
    return _linear_cards(data, keys) if data.model == "linear" else _model_cards(data, keys)
