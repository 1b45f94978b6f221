// The workbench page: every control edits the request, every figure comes from a JSON endpoint
// (docs/workbench.md). The newest change wins: each request carries an id, and a response whose id
// is not the newest one's is never shown (the server also cancels the older computation).
"use strict";

const UNITS = { arcmin: "arcmin", nm_per_arcmin: "N·m/arcmin", um: "µm", arcsec: "arcsec" };
const TITLES = { backlash: "Backlash", lost_motion: "Lost motion", rigidity: "Torsional rigidity",
                 preload: "Preload", transmission_error: "TE peak-to-peak",
                 lost_motion_max: "Largest rigid lost motion over a revolution" };
// the specs each model reads: request key -> label (the command line's --spec-... flags)
const SPECS = {
  linear: { arcmin: "backlash ≤ [arcmin]" },
  contact: { arcmin: "backlash ≤ [arcmin]", preload_um: "preload ≤ [µm]", te_arcsec: "TE p-p ≤ [arcsec]" },
  elastic: { lost_motion_arcmin: "lost motion ≤ [arcmin]", rigidity_nm_per_arcmin: "rigidity ≥ [N·m/arcmin]",
             preload_um: "preload ≤ [µm]" },
  transmission: { arcmin: "backlash ≤ [arcmin]", te_arcsec: "TE p-p ≤ [arcsec]" },
};
const PAGE = "page-" + Math.random().toString(36).slice(2, 10);  // this page's channels

const state = {
  design: null, origin: null, edits: {}, controls: null,
  // each model's own specs (a TE spec would turn the contact model into the transmission model)
  specs: { linear: { arcmin: 3 }, contact: { arcmin: 3 }, elastic: { lost_motion_arcmin: 1.5, rigidity_nm_per_arcmin: 200 },
           transmission: { arcmin: 3, te_arcsec: 60 } },
  trade: [],  // the points of lost motion against life seen since the design was loaded
  seq: 0, demandSeq: 0, shown: 0, lastJson: null, demandId: null, demandTimer: null,
};
window.workbench = state;  // for scripts and the browser test

const $ = (sel) => document.querySelector(sel);
const el = (tag, attrs = {}, ...children) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "class") e.className = v; else if (k === "text") e.textContent = v;
    else if (k.startsWith("data-")) e.setAttribute(k, v); else e[k] = v;
  }
  for (const c of children) e.append(c);
  return e;
};

async function post(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "Content-Type": "application/json" },
                                body: JSON.stringify(body) });
  return r;
}
async function errorOf(r) {
  try { return await r.json(); } catch (e) { return { error: `HTTP ${r.status}` }; }
}

function fmt(x, digits = 4) {
  if (x === null || x === undefined || !isFinite(x)) return "–";
  const a = Math.abs(x);
  if (a >= 1000) return x.toFixed(1);
  if (a >= 100) return x.toFixed(2);
  return x.toFixed(digits);
}
const pct = (x) => (x === null || x === undefined) ? "–" : (100 * x).toFixed(2) + " %";

// --- requests -------------------------------------------------------------------------------

function model() { return $("#model").value; }
function specsForModel() {
  const out = {};
  const mine = state.specs[model()] || {};
  for (const key of Object.keys(SPECS[model()] || {})) {
    const v = mine[key];
    if (v !== null && v !== undefined && v !== "") out[key] = v;
  }
  return out;
}
function numberOf(input) {
  const t = input.value.trim();
  if (t === "") return null;
  const v = Number(t);
  return Number.isFinite(v) ? v : t;  // a non-number goes as it is: the server names it
}
function baseBody() {
  return { design: state.design, origin: state.origin, edits: state.edits };
}
function runBody() {
  return { ...baseBody(), model: model(), samples: numberOf($("#samples")), seed: numberOf($("#seed")),
           specs: specsForModel() };
}

// --- errors next to their control --------------------------------------------------------------

function clearErrors(root = $("#controls"), extra = "#design-error, #run-error") {
  root.querySelectorAll("[data-field]").forEach((e) => e.classList.remove("invalid"));
  root.querySelectorAll("[data-field] .err").forEach((e) => { e.textContent = ""; });
  document.querySelectorAll(extra).forEach((e) => { e.textContent = ""; });
}
function showError(field, message, root = $("#controls"), fallback = "#run-error") {
  // the control in root whose field (the request's field the server names) is the error's field or
  // holds it (factors.x for factors.x.lower_um); else the fallback line
  let best = null;
  root.querySelectorAll("[data-field]").forEach((e) => {
    const f = e.dataset.field;
    if ((field === f || field.startsWith(f + ".") || f.startsWith(field + ".")) &&
        (!best || f.length > best.dataset.field.length) && e.querySelector(".err")) best = e;
  });
  if (best) {
    best.classList.add("invalid");
    best.querySelector(".err").textContent = message;
  } else {
    $(fallback).textContent = message;
  }
}

// --- the controls of a design ------------------------------------------------------------------

function fieldRow(field, label, input) {
  return el("div", { class: "row", "data-field": field }, el("label", {}, label, input), el("span", { class: "err" }));
}

function buildSpecs() {
  const box = $("#specs");
  box.replaceChildren();
  for (const [key, label] of Object.entries(SPECS[model()] || {})) {
    const mine = state.specs[model()];
    const input = el("input", { type: "number", step: "any", id: "spec-" + key, value: mine[key] ?? "" });
    input.addEventListener("change", () => { mine[key] = numberOf(input); update(); });
    box.append(fieldRow("specs." + key, label, input));
  }
}

function buildControls(c) {
  state.controls = c;
  $("#design-name").textContent = `${c.name} (${c.origin})`;
  const models = $("#model"), current = models.value;
  models.replaceChildren(...c.models.map((m) => el("option", { value: m, text: m })));
  models.value = c.models.includes(current) ? current : (c.models.includes("elastic") ? "elastic" : "linear");
  buildSpecs();
  const grades = $("#grades");
  grades.replaceChildren();
  if (!c.grades) grades.append(el("p", { class: "note", text: "This design gives every zone explicitly (no [grades])." }));
  else for (const stage of ["involute", "cycloid", "crank"]) {
    const select = el("select", { id: "grade-" + stage });
    select.append(el("option", { value: "", text: "–" }));
    for (let g = c.grades.range[0]; g <= c.grades.range[1]; g++) select.append(el("option", { value: String(g), text: String(g) }));
    select.value = c.grades[stage] === null ? "" : String(c.grades[stage]);
    select.addEventListener("change", () => {
      state.edits["grades." + stage] = select.value === "" ? null : Number(select.value);
      update();
    });
    grades.append(fieldRow("grades." + stage, stage + (stage === "crank" ? " (ISO 286 IT)" : " (ISO 1328-1)"), select));
  }
  const mods = $("#modifications");
  mods.replaceChildren();
  for (const [path, value] of Object.entries(c.modifications)) {
    const input = el("input", { type: "number", step: "any", value: value, id: "mod-" + path.split(".")[1] });
    input.addEventListener("change", () => { state.edits[path] = numberOf(input); update(); });
    const name = path.split(".")[1].replace("_modification_um", "").replace("_", " ");
    mods.append(fieldRow(path, name, input));
  }
  const body = $("#factors tbody");
  body.replaceChildren();
  for (const f of c.factors) {
    const lo = el("input", { type: "number", step: "any", value: +f.lower_um.toFixed(3), id: `zone-${f.key}-lower` });
    const hi = el("input", { type: "number", step: "any", value: +f.upper_um.toFixed(3), id: `zone-${f.key}-upper` });
    const set = () => {
      state.edits[`factors.${f.key}.plus_minus_um`] = null;
      state.edits[`factors.${f.key}.lower_um`] = numberOf(lo);
      state.edits[`factors.${f.key}.upper_um`] = numberOf(hi);
      update();
    };
    lo.addEventListener("change", set);
    hi.addEventListener("change", set);
    const row = el("tr", { class: f.explicit ? "explicit" : "", "data-field": "factors." + f.key },
      el("td", { class: "name" }, `${f.id}. ${f.name}`, el("span", { class: "origin", text: f.origin, title: f.origin }),
         el("span", { class: "err" })),
      el("td", {}, lo), el("td", {}, hi));
    body.append(row);
  }
}

function refreshZones(c) {
  // the resolved zones after a grade change (inputs the user is in are left alone)
  for (const f of c.factors) {
    const row = document.querySelector(`tr[data-field="factors.${f.key}"]`);
    if (!row) continue;
    row.className = f.explicit ? "explicit" : "";
    row.querySelector(".origin").textContent = f.origin;
    row.querySelector(".origin").title = f.origin;
    for (const [side, v] of [["lower", f.lower_um], ["upper", f.upper_um]]) {
      const input = $(`#zone-${f.key}-${side}`);
      if (input && document.activeElement !== input) input.value = +v.toFixed(3);
    }
  }
}

// --- the figures -----------------------------------------------------------------------------

function tailOf(o) {
  const table = (o.quantiles && o.quantiles.table) || [];
  const p = o.spec_is_upper === false ? 0.00135 : 0.99865;
  return table.find((q) => Math.abs(q.probability - p) < 1e-9) || null;
}

function intervalText(q) {
  // a quantile's 95 % interval; an end the sample cannot bound is open (bounded false, the end null)
  if (q.bounded !== false) return `[${fmt(q.ci95_low)}, ${fmt(q.ci95_high)}]`;
  const end = (v) => (v === null || v === undefined ? "beyond the sample" : fmt(v));
  const needs = q.needs_samples ? ` (needs ≥ ${q.needs_samples.toLocaleString("en")} units)` : "";
  return `[${end(q.ci95_low)}, ${end(q.ci95_high)}]${needs}`;
}

function card(name, o) {
  const unit = UNITS[o.unit] || o.unit;
  const tail = tailOf(o);
  const dl = el("dl");
  const item = (label, key, value, text, ci) => {
    dl.append(el("dt", { text: label }));
    const dd = el("dd");
    const v = el("span", { "data-key": key, "data-value": String(value), text });
    dd.append(v);
    if (ci) dd.append(el("span", { class: "ci", text: " " + ci }));
    dl.append(dd);
  };
  item("σ", `${name}.sigma`, o.sigma, fmt(o.sigma));
  if (tail) item(`${(100 * tail.probability).toFixed(3)} % tail`, `${name}.tail`, tail.value, fmt(tail.value),
                 intervalText(tail));
  const c = el("div", { class: "card", "data-output": name },
    el("h3", { text: `${TITLES[name] || name} [${unit}]`, title: o.description }),
    el("div", {}, el("span", { class: "big", "data-key": `${name}.mean`, "data-value": String(o.mean), text: fmt(o.mean) }),
       el("span", { class: "ci", text: ` mean [${fmt(o.mean_ci95_low)}, ${fmt(o.mean_ci95_high)}]` })),
    dl);
  if (o.yield) {
    const y = o.yield;
    c.append(el("div", { class: "yieldline" },
      el("span", { text: `yield (${o.spec_is_upper ? "≤" : "≥"} ${o.spec_limit}) ` }),
      el("b", { "data-key": `${name}.yield`, "data-value": String(y.fraction), text: pct(y.fraction) }),
      el("span", { class: "ci", text: ` [${pct(y.ci95_low)}, ${pct(y.ci95_high)}]` })));
  }
  // a warning the figures carry (e.g. a lost motion read in friction's stick band): on the card itself
  if (o.warning) c.append(el("div", { class: "warn", "data-warning": name, text: "⚠ " + o.warning }));
  return c;
}

function renderSimulation(data) {
  const cards = $("#cards");
  cards.replaceChildren();
  const names = Object.keys(data.outputs);
  const j = data.joint_yield;
  if (j && typeof j === "object" && j.fraction !== undefined) {
    cards.append(el("div", { class: "card yield" }, el("h3", { text: "All specs at once (joint yield)" }),
      el("div", {}, el("span", { class: "big", "data-key": "joint.yield", "data-value": String(j.fraction),
                                  text: pct(j.fraction) })),
      el("div", { class: "ci", text: `95 % interval [${pct(j.ci95_low)}, ${pct(j.ci95_high)}]` })));
  }
  for (const name of names) cards.append(card(name, data.outputs[name]));
  const hist = $("#histograms");
  const keep = new Set(names.map((n) => "hist-" + n));
  [...hist.children].forEach((c) => { if (!keep.has(c.id)) { Plotly.purge(c); c.remove(); } });
  for (const name of names) {
    const o = data.outputs[name];
    let div = document.getElementById("hist-" + name);
    if (!div) { div = el("div", { id: "hist-" + name, class: "fig" }); hist.append(div); }
    const e = o.histogram.edges, x = [], w = [];
    for (let i = 0; i + 1 < e.length; i++) { x.push(0.5 * (e[i] + e[i + 1])); w.push(e[i + 1] - e[i]); }
    const unit = UNITS[o.unit] || o.unit;
    const shapes = [];
    if (o.spec_limit !== null && o.spec_limit !== undefined)
      shapes.push({ type: "line", x0: o.spec_limit, x1: o.spec_limit, yref: "paper", y0: 0, y1: 1,
                    line: { color: "#b3261e", width: 2, dash: "dash" } });
    Plotly.react(div, [{ type: "bar", x, y: o.histogram.counts, width: w, marker: { color: "#4c78a8" },
                         hovertemplate: "%{x:.4g}: %{y} units<extra></extra>" }],
      { title: { text: `${TITLES[name] || name}: ${o.samples} units`, font: { size: 13 } }, height: 280,
        margin: { l: 50, r: 10, t: 36, b: 40 }, xaxis: { title: { text: `[${unit}]` } }, yaxis: { title: { text: "units" } },
        shapes, bargap: 0, annotations: shapes.length ? [{ x: o.spec_limit, yref: "paper", y: 1, text: "spec",
        showarrow: false, font: { color: "#b3261e" }, xanchor: "left" }] : [] },
      { displayModeBar: false, responsive: true });
  }
}

function loopTrace(unit, name, style) {
  // one closed loop: the four branches joined (load+, unload+, load-, unload-)
  const x = [], y = [];
  for (const b of unit.loop) { x.push(...b.angle_arcmin, null); y.push(...b.torque_nm, null); }
  return { type: "scatter", mode: "lines", name, x, y, line: style };
}

function renderLoop(section) {
  const h = section.nominal;
  const traces = [loopTrace(h, `nominal: ${fmt(h.lost_motion_arcmin, 3)} arcmin`, { color: "#1d2733", width: 2.5 })];
  const colours = ["#2f9e44", "#e8590c", "#1864ab", "#9c36b5"];
  Object.entries(section.quantile_units || {}).forEach(([q, u], i) =>
    traces.push(loopTrace(u, `${q} unit: ${fmt(u.lost_motion_arcmin, 3)} arcmin`, { color: colours[i % 4], dash: "dash" })));
  Plotly.react($("#fig-loop"), traces, {
    title: { text: `nominal unit: lost motion ${fmt(h.lost_motion_arcmin)} arcmin, backlash ${fmt(h.backlash_arcmin)} arcmin, ` +
                   `rigidity ${fmt(h.torsional_rigidity_nm_per_arcmin)} N·m/arcmin; beside it the units at the 5 % and ` +
                   `95 % quantiles of lost motion (of 2000)`, font: { size: 12 } },
    height: 340, margin: { l: 60, r: 10, t: 40, b: 45 },
    xaxis: { title: { text: "output angle [arcmin]" } }, yaxis: { title: { text: "torque [N·m]" } } },
    { displayModeBar: false, responsive: true });
  const rows = Object.keys(h.compliance_share).filter((k) => h.compliance_share[k] > 0 || h.lost_motion_share_arcmin[k] > 0);
  const t = el("table", { class: "plain" }, el("tr", {}, ...["element", "lost motion [arcmin]", "share of compliance"].map((s) => el("th", { text: s }))));
  for (const k of rows) t.append(el("tr", {}, el("td", { text: k.replace(/_/g, " ") }),
    el("td", { text: fmt(h.lost_motion_share_arcmin[k]) }), el("td", { text: pct(h.compliance_share[k]) })));
  const warnings = (h.warnings || []).map((w) => el("div", { class: "warn", "data-warning": "loop", text: "⚠ " + w }));
  $("#loop-shares").replaceChildren(...warnings, t);
}

// a card's list of figures: [the <dl>, item(text, key, value, shown, note)], each value a span whose data-key
// is its path in the command line's JSON (the browser tests read them)
function cardList() {
  const dl = el("dl");
  const item = (text, key, value, shown, note) => {
    dl.append(el("dt", { text }));
    const dd = el("dd", {}, el("span", { "data-key": key, "data-value": String(value), text: shown }));
    if (note) dd.append(el("span", { class: "ci", text: " " + note }));
    dl.append(dd);
  };
  return [dl, item];
}

// the capacity card: the edited design's datasheet and its point of lost motion against life; every
// what-if seen since the design was loaded stays on the figure (state.trade), the loaded design's first
function whatIfLabel(edits) {
  const keys = Object.keys(edits);
  if (!keys.length) return "the design as loaded";
  return keys.map((k) => `${k.split(".").slice(-2).join(".")} = ${edits[k]}`).join(", ");
}

function renderCapacity(data, edits) {
  const c = data.capacity, p = data.trade.points[0];
  const label = whatIfLabel(edits);
  state.trade = state.trade.filter((q) => q.label !== label);
  state.trade.push({ label, lost_motion_arcmin: p.lost_motion_arcmin, reducer_life_h: p.reducer_life_h,
                     derived_rated_torque_nm: p.derived_rated_torque_nm });
  const [dl, item] = cardList();
  const h = (x) => (x === null || x === undefined) ? "–" : Math.round(x).toLocaleString("en");
  const m = c.main_bearings;
  item("derived rated torque [N·m]", "capacity.derived_rated_torque_nm", c.derived_rated_torque_nm,
       h(c.derived_rated_torque_nm), `(L10 = ${c.rated_life_h} h at ${c.rated_output_speed_rpm} r/min; stated ${c.stated_rated_torque_nm})`);
  item(`reducer L10 at ${c.stated_rated_torque_nm} N·m [h]`, "capacity.reducer_life_h", c.reducer_life_h, h(c.reducer_life_h),
       `(weakest: ${c.weakest_bearing}, ${h(c.weakest_bearing_life_h)} h)`);
  item("momentary maximum torque [N·m]", "capacity.momentary_maximum_torque_nm", c.momentary_maximum_torque_nm,
       h(c.momentary_maximum_torque_nm), `(limited by the ${c.limiting_element})`);
  item("moment rigidity [N·m/arcmin]", "capacity.moment_rigidity_nm_per_arcmin", m ? m.moment_rigidity_nm_per_arcmin : null,
       m ? h(m.moment_rigidity_nm_per_arcmin) : "–", m ? "(main bearings)" : "(no main bearings in [structure])");
  item("allowable moment [N·m]", "capacity.allowable_moment_nm", m ? m.allowable_moment_nm : null,
       m ? h(m.allowable_moment_nm) : "–");
  item("lost motion [arcmin]", "trade.lost_motion_arcmin", p.lost_motion_arcmin, fmt(p.lost_motion_arcmin, 3),
       `↔ L10 ${h(p.reducer_life_h)} h (this what-if)`);
  $("#capacity-card").replaceChildren(
    el("h3", { text: `${c.design_name}: ${label}`, title: "rvbacklash capacity (docs/capacity.md), the edited design" }),
    el("div", {}, el("span", { class: "big", "data-key": "capacity.limiting_element", "data-value": c.limiting_element,
                               text: `${h(c.momentary_maximum_torque_nm)} N·m` }),
       el("span", { class: "ci", text: ` momentary maximum: ${c.limiting_element}` })), dl,
    el("div", { class: "note", text: `${c.life_method}, ${c.crank_angles} crank angles; the command line: rvbacklash capacity` }));
  const current = state.trade[state.trade.length - 1];
  const others = state.trade.slice(0, -1);
  Plotly.react($("#fig-trade"), [
    { type: "scatter", mode: "markers+text", name: "what-ifs seen", x: others.map((q) => q.lost_motion_arcmin),
      y: others.map((q) => q.reducer_life_h), text: others.map((q) => q.label), textposition: "top center",
      textfont: { size: 9 }, marker: { color: "#4c78a8", size: 8 } },
    { type: "scatter", mode: "markers", name: `now: ${current.label}`, x: [current.lost_motion_arcmin],
      y: [current.reducer_life_h], marker: { color: "#c92a2a", size: 12, symbol: "diamond" } }],
    { title: { text: "lost motion against life (nominal unit)", font: { size: 12 } }, height: 320,
      margin: { l: 65, r: 10, t: 36, b: 45 }, showlegend: true, legend: { orientation: "h", y: -0.25, font: { size: 10 } },
      xaxis: { title: { text: "lost motion [arcmin]" } }, yaxis: { title: { text: `reducer L10 at ${c.stated_rated_torque_nm} N·m [h]` } },
      shapes: [{ type: "line", xref: "paper", x0: 0, x1: 1, y0: c.rated_life_h, y1: c.rated_life_h,
                 line: { color: "#868e96", dash: "dot", width: 1 } }] },
    { displayModeBar: false, responsive: true });
}

function renderTe(t) {
  Plotly.react($("#fig-te"), [
    { type: "scatter", mode: "lines", name: "TE ccw [arcsec]", x: t.output_angle_deg, y: t.te_ccw_arcsec },
    { type: "scatter", mode: "lines", name: "TE cw [arcsec]", x: t.output_angle_deg, y: t.te_cw_arcsec },
    { type: "scatter", mode: "lines", name: "lost motion [arcmin]", x: t.output_angle_deg, y: t.lost_motion_arcmin, yaxis: "y2" }],
    { title: { text: `TE p-p ${fmt(t.te_peak_to_peak_arcsec, 2)} arcsec (${t.unit})`, font: { size: 13 } }, height: 330,
      margin: { l: 55, r: 55, t: 36, b: 90 }, xaxis: { title: { text: "output angle [deg]" } },
      yaxis: { title: { text: "[arcsec]" } }, yaxis2: { title: { text: "[arcmin]" }, overlaying: "y", side: "right" },
      legend: { orientation: "h", y: -0.3 } }, { displayModeBar: false, responsive: true });
  const amp = t.spectrum_amplitude_arcsec;
  Plotly.react($("#fig-spectrum"), [{ type: "bar", x: amp.map((_, i) => i), y: amp, marker: { color: "#4c78a8" } }],
    { title: { text: "spectrum (orders per output revolution)", font: { size: 13 } }, height: 330,
      margin: { l: 55, r: 10, t: 36, b: 90 }, xaxis: { title: { text: "order" }, range: [0, Math.min(amp.length, 170)] },
      yaxis: { title: { text: "amplitude [arcsec]" } } }, { displayModeBar: false, responsive: true });
}

// --- the live loop: a change, its run, its figures --------------------------------------------

function setStatus(text, kind) { const s = $("#status"); s.textContent = text; s.className = kind; }

async function update() {
  const id = ++state.seq;
  const started = performance.now();
  setStatus("computing…", "busy");
  const body = { ...runBody(), request_id: id, channel: PAGE + "-simulate" };
  let r;
  try { r = await post("/api/simulate", body); } catch (e) { if (id === state.seq) setStatus(String(e), "bad"); return; }
  if (id !== state.seq || r.headers.get("X-Request-Id") !== String(id)) return;  // a newer change is under way
  if (r.status === 409) return;
  clearErrors();
  if (!r.ok) {
    const err = await errorOf(r);
    if (id !== state.seq) return;
    showError(err.field || "", err.error);
    $("#results").classList.add("stale");  // the last valid figures stay, greyed
    setStatus("invalid input: the figures shown are the last valid ones", "bad");
    return;
  }
  const text = await r.text();
  if (id !== state.seq) return;
  const data = JSON.parse(text);
  state.lastJson = text;
  renderSimulation(data);
  state.shown = id;
  $("#results").classList.remove("stale");
  setStatus(`${data.design_name}: ${data.model} model, ${data.samples_done} units, seed ${data.seed}`, "ok");
  $("#timing").textContent = `change → cards ${(performance.now() - started).toFixed(0)} ms (run ${(1000 * data.elapsed_s).toFixed(0)} ms)`;
  document.body.dataset.shown = String(id);
  secondary(id);
}

async function secondary(id) {
  // the zones after the change, the nominal loop (elastic), the nominal TE (transmission)
  post("/api/design", { ...baseBody(), request_id: id, channel: PAGE + "-design" }).then(async (r) => {
    if (r.ok && id === state.seq) refreshZones(await r.json());
  });
  const m = model();
  $("#loop-section").hidden = m !== "elastic";
  $("#te-section").hidden = m !== "transmission";
  const figure = async (path, extra, box, render) => {
    const r = await post(path, { ...baseBody(), ...extra, request_id: id, channel: PAGE + path });
    if (id !== state.seq || r.status === 409) return;
    if (!r.ok) { $(box).textContent = (await errorOf(r)).error; return; }
    $(box).textContent = "";
    render(await r.json());
  };
  if (m === "elastic") figure("/api/elastic-section", { samples: 2000, seed: numberOf($("#seed")) }, "#loop-error", renderLoop);
  // the capacity card: designs with [elastic] and [structure] (else its one line in the card's place)
  $("#capacity-section").hidden = m !== "elastic";
  if (m === "elastic") {
    const edits = { ...state.edits };
    $("#capacity-status").textContent = "computing…";
    figure("/api/capacity", {}, "#capacity-error", (data) => {
      $("#capacity-status").textContent = "";
      renderCapacity(data, edits);
      document.body.dataset.capacityShown = String(id);
    }).then(() => { if (id === state.seq && $("#capacity-error").textContent) $("#capacity-status").textContent = ""; });
  }
  // the efficiency and temperature cards: designs with [elastic] (the packaged robot-joint cycle's heat balance)
  $("#efficiency-section").hidden = m !== "elastic";
  if (m === "elastic") {
    $("#efficiency-status").textContent = "computing…";
    figure("/api/efficiency", { duty_cycle: "robot-joint" }, "#efficiency-error", (data) => {
      $("#efficiency-status").textContent = "";
      renderEfficiency(data);
      document.body.dataset.efficiencyShown = String(id);
    }).then(() => { if (id === state.seq && $("#efficiency-error").textContent) $("#efficiency-status").textContent = ""; });
  }
  // the service-life card: designs with [elastic] (the packaged robot-joint cycle; the page's lost-motion spec)
  $("#life-section").hidden = m !== "elastic";
  if (m === "elastic") {
    $("#life-status").textContent = "computing…";
    figure("/api/service-life", lifeBody(), "#life-error", (data) => {
      $("#life-status").textContent = "";
      renderLife(data);
      document.body.dataset.lifeShown = String(id);
    }).then(() => { if (id === state.seq && $("#life-error").textContent) $("#life-status").textContent = ""; });
  }
  if (m === "transmission") figure("/api/transmission-error", {}, "#te-error", renderTe);
  updateSelection(id);
}

// the selection card: the run's units assembled at random and with the classes, side by side (a what-if
// of the assembly, beside the what-ifs of the design); models that draw parts, with a spec
function updateSelection(id) {
  const m = model();
  const specs = specsForModel();
  const shown = m !== "linear" && Object.keys(specs).length > 0;
  $("#selection-section").hidden = !shown;
  if (!shown) return;
  $("#selection-status").textContent = "computing…";
  $("#selection-error").textContent = "";
  post("/api/selection", { ...runBody(), select: $("#select").value, request_id: id,
                           channel: PAGE + "-selection" }).then(async (r) => {
    if (id !== state.seq || r.status === 409) return;
    $("#selection-status").textContent = "";
    if (!r.ok) {
      const err = await errorOf(r);
      $("#selection-card").replaceChildren();
      if (!$("#select").value.trim() && err.field === "select") {  // nothing asked, no [selection] in the design
        $("#selection-card").append(el("div", { class: "note", text: "enter classes (e.g. pins=5x2um,rollers=3x2um) to " +
          "see the same units selected" }));
      } else $("#selection-error").textContent = err.error;
      return;
    }
    renderSelection(await r.json());
    document.body.dataset.selectionShown = String(id);
  });
}

function renderSelection(s) {
  const pct = (p) => p ? `${(100 * p.fraction).toFixed(2)} %` : "–";
  const t = el("table", { class: "plain" }, el("tr", {}, ...["spec", "random assembly", "selected", "gain"].map(
    (x) => el("th", { text: x }))));
  for (const y of s.yields) {
    const spec = y.output === "joint" ? "every spec (joint)" : `${y.output.replace(/_/g, " ")} ${y.output === "rigidity" ? "≥" : "≤"} ${y.spec}`;
    t.append(el("tr", {}, el("td", { text: spec }),
      el("td", {}, el("span", { "data-key": `selection.${y.output}.random`, "data-value": String(y.random.fraction), text: pct(y.random) })),
      el("td", {}, el("span", { "data-key": `selection.${y.output}.selected`, "data-value": String(y.selected.fraction), text: pct(y.selected) })),
      el("td", { text: `${(100 * (y.selected.fraction - y.random.fraction)).toFixed(2)} points` })));
  }
  $("#selection-card").replaceChildren(
    el("h3", { text: `${s.design_name}: ${s.selection.pins.count} pin classes, ${s.selection.rollers.count} roller classes`,
               title: "rvbacklash simulate --select (docs/selective-assembly.md)" }), t,
    el("div", { class: "note", text: `parts bought per unit built: pins ${s.pin_sets_per_unit.toFixed(2)} sets ` +
      `(${(100 * s.pin_surplus_fraction).toFixed(1)} % left over), rollers ${s.roller_sets_per_unit.toFixed(2)} ` +
      `(${(100 * s.roller_surplus_fraction).toFixed(1)} % left over); ${s.samples_done} units, seed ${s.seed}; ` +
      `the command line: rvbacklash simulate --select` }));
}

// the service-life card: `rvbacklash service-life --duty-cycle robot-joint --hours 0,500,1000,2000,4000,6000
// -n 500 --seed SEED --spec-lost-motion-arcmin SPEC --json` of the edited design (docs/service-life.md)
const LIFE = { duty_cycle: "robot-joint", hours: [0, 500, 1000, 2000, 4000, 6000], samples: 500 };
function lifeBody() {
  const spec = specsForModel().lost_motion_arcmin;
  return { ...LIFE, seed: numberOf($("#seed")), ...(typeof spec === "number" ? { spec_lost_motion_arcmin: spec } : {}) };
}

function renderLife(r) {
  const p = r.production, last = r.points[r.points.length - 1], first = r.points[0];
  const h = (x) => Math.round(x).toLocaleString("en");
  const [dl, item] = cardList();
  const median = p.accuracy_life_quantiles_h["50%"];  // null: beyond the last hour
  item(`nominal lost motion at ${h(first.hours)} h [arcmin]`, "life.points.0.lost_motion_arcmin", first.lost_motion_arcmin,
       fmt(first.lost_motion_arcmin, 3));
  item(`nominal lost motion at ${h(last.hours)} h [arcmin]`, `life.points.${r.points.length - 1}.lost_motion_arcmin`,
       last.lost_motion_arcmin, fmt(last.lost_motion_arcmin, 3));
  const yl = p.yield_at_hours[p.yield_at_hours.length - 1];
  item(`yield at ${h(last.hours)} h`, `life.production.yield_at_hours.${p.yield_at_hours.length - 1}.fraction`, yl.fraction,
       pct(yl.fraction), `[${pct(yl.ci95_low)}, ${pct(yl.ci95_high)}]`);
  item(`in spec for all ${h(last.hours)} h`, "life.production.accuracy_life_yield.fraction", p.accuracy_life_yield.fraction,
       pct(p.accuracy_life_yield.fraction), `(${p.out_at_start} of ${p.units} out at 0 h)`);
  $("#life-card").replaceChildren(
    el("h3", { text: `${r.design_name}: median accuracy life (lost motion ≤ ${p.spec_lost_motion_arcmin} arcmin)`,
               title: "rvbacklash service-life (docs/service-life.md), the edited design" }),
    el("div", {}, el("span", { class: "big", "data-key": "life.production.accuracy_life_quantiles_h.50%",
                               "data-value": String(median), text: median === null ? `> ${h(last.hours)} h` : `${h(median)} h` }),
       el("span", { class: "ci", text: ` of ${p.units} units, each with its own wear, seed ${p.seed}` })), dl,
    el("div", { class: "note", text: `${r.steps} time steps, ${r.crank_angles} crank angles; the command line: rvbacklash ` +
      `service-life --duty-cycle ${LIFE.duty_cycle} --hours ${LIFE.hours.join(",")} -n ${p.units} --seed ${p.seed}` }));
  const q = (i) => p.lost_motion_quantiles_arcmin.map((v) => v[i]);
  Plotly.react($("#fig-life-lm"), [
    { type: "scatter", mode: "lines+markers", name: "nominal unit", x: r.trajectory.map((t) => t.hours),
      y: r.trajectory.map((t) => t.lost_motion_arcmin), line: { color: "#1d2733", width: 2.5 } },
    { type: "scatter", mode: "lines+markers", name: "95 % unit", x: p.hours, y: q(2), line: { color: "#e8590c", dash: "dash" } },
    { type: "scatter", mode: "lines+markers", name: "median unit", x: p.hours, y: q(1), line: { color: "#2f9e44" } },
    { type: "scatter", mode: "lines+markers", name: "5 % unit", x: p.hours, y: q(0), line: { color: "#1864ab", dash: "dash" } }],
    { title: { text: `lost motion over the hours of ${LIFE.duty_cycle} (nominal unit and the run's 5 / 50 / 95 % units)`,
               font: { size: 12 } }, height: 320, margin: { l: 60, r: 10, t: 36, b: 45 },
      xaxis: { title: { text: "hours of the duty cycle [h]" } }, yaxis: { title: { text: "lost motion [arcmin]" } },
      legend: { orientation: "h", y: -0.25, font: { size: 10 } },
      shapes: [{ type: "line", xref: "paper", x0: 0, x1: 1, y0: p.spec_lost_motion_arcmin, y1: p.spec_lost_motion_arcmin,
                 line: { color: "#c92a2a", dash: "dot", width: 1.5 } }],
      annotations: [{ xref: "paper", x: 1, y: p.spec_lost_motion_arcmin, xanchor: "right", yanchor: "bottom", showarrow: false,
                      text: `spec ${p.spec_lost_motion_arcmin} arcmin`, font: { size: 10, color: "#c92a2a" } }] },
    { displayModeBar: false, responsive: true });
  const ys = p.yield_at_hours;
  Plotly.react($("#fig-life-yield"), [
    { type: "scatter", mode: "lines+markers", name: "yield", x: p.hours, y: ys.map((y) => 100 * y.fraction),
      error_y: { type: "data", symmetric: false, array: ys.map((y) => 100 * (y.ci95_high - y.fraction)),
                 arrayminus: ys.map((y) => 100 * (y.fraction - y.ci95_low)) }, line: { color: "#2f9e44" } }],
    { title: { text: `yield: lost motion ≤ ${p.spec_lost_motion_arcmin} arcmin (95 % intervals)`, font: { size: 12 } },
      height: 320, margin: { l: 60, r: 10, t: 36, b: 45 }, xaxis: { title: { text: "hours of the duty cycle [h]" } },
      yaxis: { title: { text: "yield [%]" }, range: [0, 100] } }, { displayModeBar: false, responsive: true });
}

// the efficiency card and the temperature card: `rvbacklash efficiency --json --duty-cycle robot-joint` of the
// edited design (docs/efficiency.md)
function renderEfficiency(e) {
  const list = cardList;
  const [dl, item] = list();
  const n0 = e.no_load_running_torque[0];
  const back = e.back_driving_torque_nm;
  item("total loss [W]", "efficiency.total_loss_at_rated_w", e.total_loss_at_rated_w, fmt(e.total_loss_at_rated_w, 1),
       `of ${fmt(e.output_power_at_rated_w, 0)} W out; largest: ${e.elements.reduce((a, b) => (b.loss_w > a.loss_w ? b : a)).element}`);
  item(`no-load running torque [N·m]`, "efficiency.no_load_running_torque.0.no_load_torque_nm", n0.no_load_torque_nm,
       fmt(n0.no_load_torque_nm, 3), `(input, ${n0.input_speed_rpm} r/min, ${n0.temperature_c} °C)`);
  item("starting torque [N·m]", "efficiency.starting_torque_nm", e.starting_torque_nm, fmt(e.starting_torque_nm, 4),
       `(input, no load; starting efficiency ${pct(e.starting_efficiency)})`);
  item("back-driving torque [N·m]", "efficiency.back_driving_torque_nm", back,
       (back === null || back === undefined || !Number.isFinite(Number(back))) ? "self-locking" : fmt(back, 2), "(output)");
  item("loop friction at T_R [N·m]", "efficiency.contacts_loop_friction_at_rated_nm", e.contacts_loop_friction_at_rated_nm,
       fmt(e.contacts_loop_friction_at_rated_nm, 2),
       `(from the contacts under the twist; the loop uses ${e.loop_friction_model}: ${fmt(e.stated_friction_torque_nm, 3)} N·m + ${fmt(e.loop_friction_load_fraction, 4)} |T|)`);
  $("#efficiency-card").replaceChildren(
    el("h3", { text: `${e.design_name}: efficiency`, title: "rvbacklash efficiency (docs/efficiency.md), the edited design" }),
    el("div", {}, el("span", { class: "big", "data-key": "efficiency.efficiency_at_rated", "data-value": String(e.efficiency_at_rated),
                               text: pct(e.efficiency_at_rated) }),
       el("span", { class: "ci", text: ` at ${e.rated_torque_nm} N·m, ${e.rated_output_speed_rpm} r/min, ${e.temperature_c} °C` })), dl,
    el("div", { class: "note", text: `${e.crank_angles} crank angles; the command line: rvbacklash efficiency` }));
  const th = e.thermal;
  if (!th) { $("#temperature-card").replaceChildren(el("div", { class: "note", text: "no duty cycle" })); return; }
  const [tl, titem] = list();
  const hot = th.precision[th.precision.length - 1], cold = th.precision[0];
  titem("time constant [min]", "efficiency.thermal.time_constant_min", th.time_constant_min, fmt(th.time_constant_min, 0));
  titem(`allowable duty at ${th.case_limit_c} °C`, "efficiency.thermal.allowable_duty_at_limit", th.allowable_duty_at_limit,
        pct(th.allowable_duty_at_limit));
  titem(`lost motion at ${fmt(hot.temperature_c, 1)} °C [arcmin]`, `efficiency.thermal.precision.${th.precision.length - 1}.lost_motion_arcmin`,
        hot.lost_motion_arcmin, fmt(hot.lost_motion_arcmin, 3), `(${fmt(cold.lost_motion_arcmin, 3)} at ${cold.temperature_c} °C)`);
  titem(`backlash at ${fmt(hot.temperature_c, 1)} °C [arcmin]`, `efficiency.thermal.precision.${th.precision.length - 1}.backlash_arcmin`,
        hot.backlash_arcmin, fmt(hot.backlash_arcmin, 3), `(${fmt(cold.backlash_arcmin, 3)} at ${cold.temperature_c} °C)`);
  titem(`TE at ${fmt(hot.temperature_c, 1)} °C [arcsec]`, `efficiency.thermal.precision.${th.precision.length - 1}.te_peak_to_peak_arcsec`,
        hot.te_peak_to_peak_arcsec, fmt(hot.te_peak_to_peak_arcsec, 3),
        `(the nominal unit's peak-to-peak with its parts' expansion, against its curve at ${cold.temperature_c} °C)`);
  $("#temperature-card").replaceChildren(
    el("h3", { text: `steady case temperature: ${th.duty_cycle}`, title: "the duty cycle's heat balance (docs/efficiency.md)" }),
    el("div", {}, el("span", { class: "big", "data-key": "efficiency.thermal.steady_temperature_c",
                               "data-value": String(th.steady_temperature_c), text: `${fmt(th.steady_temperature_c, 1)} °C` }),
       el("span", { class: "ci", text: ` (${fmt(th.loss_at_steady_w, 1)} W, ambient ${th.ambient_c} °C${th.steady_temperature_c > th.case_limit_c ? "; above the case limit" : ""})` })),
    tl, el("div", { class: "note", text: "the command line: rvbacklash efficiency --duty-cycle " + th.duty_cycle }));
}

// --- on demand: Sobol, allocation, report; progress and cancel ---------------------------------

function startProgress(id) {
  state.demandId = id;
  $("#progress-row").hidden = false;
  $("#progress").removeAttribute("value");
  $("#progress-text").textContent = "starting…";
  $("#demand-error").textContent = "";
  clearInterval(state.demandTimer);
  state.demandTimer = setInterval(async () => {
    const r = await fetch("/api/progress?id=" + encodeURIComponent(id));
    if (!r.ok) return;
    const j = await r.json();
    if (j.total) { $("#progress").max = j.total; $("#progress").value = j.done; }
    $("#progress-text").textContent = `${j.state}${j.total ? `: ${j.done} of ${j.total}` : ""}`;
  }, 300);
}
function endProgress() { clearInterval(state.demandTimer); $("#progress-row").hidden = true; state.demandId = null; }

async function onDemand(path, body, done, controls) {
  // controls: the group of this job's own controls (an error about one shows beside it); else the
  // run's controls on the left (the report reads them), else the line under the buttons
  const id = `${PAGE}-${path.split("/").pop()}-${++state.demandSeq}`;  // not the live changes' counter
  clearErrors($("#demand"), "#demand-error");
  startProgress(id);
  const r = await post(path, { ...baseBody(), ...body, request_id: id, channel: PAGE + "-demand" });
  if (state.demandId !== id) return;
  endProgress();
  if (r.status === 409) { $("#demand-error").textContent = "cancelled"; return; }
  if (!r.ok) {
    const err = await errorOf(r);
    showError(err.field || "", err.error, controls || $("#controls"), "#demand-error");
    return;
  }
  await done(r);
}

function renderSobol(s) {
  const g = [...s.groups].sort((a, b) => a.total - b.total);
  const div = $("#fig-sobol");
  div.hidden = false;
  Plotly.react(div, [
    { type: "bar", orientation: "h", name: "first order", y: g.map((x) => x.input), x: g.map((x) => x.first),
      error_x: { type: "data", symmetric: false, array: g.map((x) => x.first_ci95_high - x.first),
                 arrayminus: g.map((x) => x.first - x.first_ci95_low) } },
    { type: "bar", orientation: "h", name: "total", y: g.map((x) => x.input), x: g.map((x) => x.total) }],
    { title: { text: `What to tighten: Sobol indices of ${s.output} (${s.model} model, N = ${s.samples})`, font: { size: 13 } },
      barmode: "group", height: 120 + 26 * g.length, margin: { l: 190, r: 10, t: 36, b: 40 } },
    { displayModeBar: false, responsive: true });
}

function renderAllocation(a) {
  const t = el("table", { class: "plain" }, el("tr", {}, el("th", { text: "part group" }), el("th", { text: "grade" })));
  for (const [group, grade] of Object.entries(a.grades)) t.append(el("tr", {}, el("td", { text: group.replace(/_/g, " ") }), el("td", { text: String(grade) })));
  $("#allocation").replaceChildren(
    el("p", { text: `Cheapest grades for ${a.binding.constraint} (${a.model} model): cost ${fmt(a.cost, 2)} ` +
                    `against ${fmt(a.baseline.cost, 2)} for uniform grade ${a.baseline.grade}; yield ${pct(a.yield.fraction)}.` }), t);
}

function download(name, blob) {
  const a = el("a", { href: URL.createObjectURL(blob), download: name });
  document.body.append(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// --- start ------------------------------------------------------------------------------------

async function loadDesign(design, origin, edits = {}) {
  const r = await post("/api/design", { design, origin, edits });
  if (!r.ok) {  // refused with the one line the command line gives; the current design stays
    $("#design-error").textContent = (await errorOf(r)).error;
    return false;
  }
  Object.assign(state, { design, origin, edits, trade: [] });
  $("#design-error").textContent = "";
  buildControls(await r.json());
  await update();
  return true;
}

async function start() {
  const init = await (await fetch("/api/initial")).json();
  const status = await (await fetch("/api/status")).json();
  const ex = $("#example");
  ex.replaceChildren(...status.examples.map((n) => el("option", { value: n, text: n })));
  if (!status.examples.includes(init.design)) ex.prepend(el("option", { value: "", text: init.origin || "(given design)" }));
  ex.value = status.examples.includes(init.design) ? init.design : "";
  ex.addEventListener("change", () => { if (ex.value) loadDesign(ex.value, null); });
  $("#upload").addEventListener("change", async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    if (await loadDesign(await file.text(), file.name)) {
      ex.prepend(el("option", { value: "", text: file.name }));
      ex.value = "";
    }
    e.target.value = "";
  });
  document.body.addEventListener("dragover", (e) => e.preventDefault());
  document.body.addEventListener("drop", async (e) => {
    e.preventDefault();
    const file = e.dataTransfer.files[0];
    if (file && await loadDesign(await file.text(), file.name)) ex.value = "";
  });
  $("#model").addEventListener("change", () => { buildSpecs(); update(); });
  $("#samples").addEventListener("change", update);
  $("#seed").addEventListener("change", update);
  $("#select").addEventListener("change", () => updateSelection(state.seq));
  $("#run-sobol").addEventListener("click", () => onDemand("/api/sensitivity",
    { model: model() === "transmission" ? "contact" : model(), samples: numberOf($("#sobol-n")), seed: numberOf($("#seed")) },
    async (r) => renderSobol(await r.json()), $("#sobol-group")));
  $("#run-allocate").addEventListener("click", () => {
    const m = $("#alloc-model").value;
    const spec = m === "elastic" ? state.specs.elastic.lost_motion_arcmin : (state.specs[m].arcmin ?? 3);
    onDemand("/api/allocate", { model: m, spec_arcmin: spec, yield: numberOf($("#alloc-yield")),
                                samples: m === "linear" ? undefined : 2000, seed: numberOf($("#seed")) },
             async (r) => renderAllocation(await r.json()), $("#alloc-group"));
  });
  $("#run-report").addEventListener("click", () => onDemand("/api/report", runBody(),
    async (r) => download("report.html", await r.blob())));
  $("#cancel").addEventListener("click", () => { if (state.demandId) post("/api/cancel", { id: state.demandId }); });
  $("#dl-design").addEventListener("click", async () => {
    const r = await post("/api/design", { ...baseBody(), format: "toml" });
    if (r.ok) download(`${state.controls ? state.controls.name : "design"}.toml`, await r.blob());
    else { const err = await errorOf(r); showError(err.field || "", err.error); }
  });
  $("#dl-json").addEventListener("click", () => {
    if (state.lastJson) download("simulate.json", new Blob([state.lastJson], { type: "application/json" }));
  });
  $("#dl-csv").addEventListener("click", async () => {
    const r = await post("/api/simulate", { ...runBody(), format: "csv" });
    if (r.ok) download("simulate.csv", await r.blob());
  });
  await loadDesign(init.design, init.origin);
}

start();
