// The status page's and console's script (status/status_page.html), served as
// /status_page.js: the Content-Security-Policy allows no inline script
// (docs/web-console.md, "Headers and host names").
"use strict";
const POLL_MS = 400;        // about 2.5 updates a second
const TIMEOUT_MS = 2500;    // a request not answered by then counts as the gateway unreachable
const HISTORY_MS = 2000;    // an open graph is redrawn this often
const STATUS_EVERY = 5;     // /api/status with every 5th poll: the role changes seldom
// mapping/derived_state.h alarm_bit
const ALARMS = [[1, "X high"], [2, "X low"], [4, "Y high"], [8, "Y low"], [16, "tilt high"],
                [32, "rate of change"]];

const cards = new Map();    // sensor name -> {root, parts, last}
const busRows = new Map();  // bus name -> {root, parts}
const rates = new Map();    // key -> {count, at, rate}: polls/s when the API gives none
let unreachableSince = null;
let openSensor = null;
let historyTimer = null;

const $ = (id) => document.getElementById(id);
function esc(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({"&": "&amp;", "<": "&lt;", ">": "&gt;",
                                                    "\"": "&quot;", "'": "&#39;"})[c]);
}
function pad(n) { return String(n).padStart(2, "0"); }
function clock(date) { return pad(date.getHours()) + ":" + pad(date.getMinutes()) + ":" + pad(date.getSeconds()); }
function degrees(v) { return v === null || v === undefined ? "\u2013" : v.toFixed(3) + "\u00B0"; }
function age(ms) {
  if (ms === null || ms === undefined) return "no reading";
  if (ms < 10000) return (ms / 1000).toFixed(1) + " s ago";
  if (ms < 120000) return Math.round(ms / 1000) + " s ago";
  if (ms < 7200000) return Math.round(ms / 60000) + " min ago";
  return Math.round(ms / 3600000) + " h ago";
}
function perSecond(v) { return v === null || v === undefined ? "\u2013" : (v < 10 ? v.toFixed(1) : v.toFixed(0)); }

// A counter's rate over the last updates, for a gateway whose API has no polls_per_s.
function rateOf(key, count) {
  const now = performance.now();
  const r = rates.get(key);
  if (!r || count < r.count) { rates.set(key, {count, at: now, rate: null}); return null; }
  if (now - r.at >= 2000) {
    r.rate = (count - r.count) * 1000 / (now - r.at);
    r.count = count; r.at = now;
  }
  return r.rate;
}

// A 401 means the session is gone (logged out elsewhere, expired): not an unreachable gateway.
class LoggedOut extends Error {}

// A GET's body as `read` takes it (the reply's json or text), within TIMEOUT_MS.
async function getBody(path, read) {
  const abort = new AbortController();
  const timer = setTimeout(() => abort.abort(), TIMEOUT_MS);
  try {
    const reply = await fetch(path, {cache: "no-store", signal: abort.signal});
    if (reply.status === 401) { showLogin(); throw new LoggedOut(path); }
    if (!reply.ok) throw new Error(path + ": " + reply.status);
    return await read(reply);
  } finally {
    clearTimeout(timer);
  }
}

function getJson(path) { return getBody(path, (reply) => reply.json()); }
function getText(path) { return getBody(path, (reply) => reply.text()); }

function stateOf(s) {
  // Another device answers at the sensor's address: nothing it says is the sensor's.
  if (s.wrong_device) return ["wrong", "wrong device"];
  if (!s.online) return ["offline", "offline"];
  if (s.x === null || s.x === undefined) return ["none", "no reading"];
  if (s.stale) return ["stale", "stale"];
  return ["online", "online"];
}

// The gauge's full scale: the smallest of these that holds the tilt with some room.
const SCALES = [0.5, 1, 2, 5, 10, 20, 45, 90, 180];
function gaugeScale(x, y) {
  const m = Math.hypot(x || 0, y || 0);
  return SCALES.find((s) => m <= 0.8 * s) || 180;
}

function newCard(s) {
  const root = document.createElement("article");
  root.className = "card none";
  root.tabIndex = 0;
  root.setAttribute("role", "button");
  root.dataset.name = s.name;
  root.dataset.changes = "0";
  root.innerHTML =
    '<div class="head"><span class="name"></span><span class="pill"></span></div>' +
    '<div class="meta"></div><div class="meta where"></div>' +
    '<div class="body"><div class="gauge-box">' +
    '<svg class="gauge" viewBox="-1.1 -1.1 2.2 2.2" aria-hidden="true">' +
    '<circle class="face" r="1"/><circle class="ring" r="0.4"/>' +
    '<line class="cross" x1="-1" y1="0" x2="1" y2="0"/><line class="cross" x1="0" y1="-1" x2="0" y2="1"/>' +
    '<circle class="bubble" r="0.2" cx="0" cy="0"/></svg>' +
    '<span class="scale num" title="full scale of the tilt gauge"></span></div>' +
    '<div class="angles num"><span class="axis x">X</span><span class="value x">\u2013</span>' +
    '<span class="axis y">Y</span><span class="value y">\u2013</span></div></div>' +
    '<div class="foot num"><span class="age"></span><span class="rate"></span><span class="errors"></span></div>' +
    '<div class="alarms"></div>';
  const q = (sel) => root.querySelector(sel);
  const parts = {name: q(".name"), pill: q(".pill"), meta: q(".meta"), where: q(".where"), bubble: q(".bubble"),
                 scale: q(".scale"), x: q(".value.x"), y: q(".value.y"), yAxis: q(".axis.y"),
                 age: q(".age"), rate: q(".rate"), errors: q(".errors"), alarms: q(".alarms")};
  root.addEventListener("click", () => openHistory(s.name));
  root.addEventListener("keydown", (e) => { if (e.key === "Enter" || e.key === " ") { e.preventDefault(); openHistory(s.name); } });
  return {root, parts, last: null};
}

// Failures by cause, keyed as the API's "failures" and "failures_10min".
const CAUSES = [["polls_failed", "failed polls"], ["timeout", "time-outs"], ["checksum", "checksum errors"],
                ["io_error", "port errors"], ["late_reply", "late replies"]];
function exchangeErrors(f) {
  return f ? CAUSES.slice(1).reduce((sum, [key]) => sum + (f[key] || 0), 0) : 0;
}

// A card's line of errors: red only for errors in the last 10 minutes, so one old late reply
// does not leave a healthy sensor red; those since start beside them, grey.
function errorsText(s) {
  if (s.failures && typeof s.failures === "object") {
    const total = exchangeErrors(s.failures);
    if (total === 0) return ["no errors", false];
    const since = total + " since start";
    if (!s.failures_10min) return [total + " error" + (total === 1 ? "" : "s") + " since start", true];
    const recent = exchangeErrors(s.failures_10min);
    if (recent === 0) return ["no errors in 10 min \u00B7 " + since, false];
    const named = CAUSES.slice(1).filter(([key]) => s.failures_10min[key] > 0)
      .map(([key, word]) => s.failures_10min[key] + " " + word);
    return [named.join(", ") + " in 10 min \u00B7 " + since, true];
  }
  const failed = s.polls_failed || 0;
  return failed === 0 ? ["no errors", false] : [failed + " failed poll" + (failed === 1 ? "" : "s"), true];
}

// A table of counters: each cause in the last 10 minutes and since start (or the last reset).
function countersHtml(failures, recent, extra) {
  const cell = (f, key) => f ? String(f[key] || 0) : "\u2013";
  let rows = CAUSES.map(([key, word]) =>
    "<tr><td>" + esc(word) + '</td><td class="num' + (recent && recent[key] > 0 ? " bad" : "") + '">' +
    cell(recent, key) + '</td><td class="num">' + cell(failures, key) + "</td></tr>").join("");
  for (const [word, value] of extra || [])
    rows += "<tr><td>" + esc(word) + '</td><td class="num">\u2013</td><td class="num">' + esc(value) + "</td></tr>";
  return '<table class="list counters"><thead><tr><th>Counter</th><th>Last 10 min</th><th>Since start</th>' +
         "</tr></thead><tbody>" + rows + "</tbody></table>";
}

// An admin's reset of a sensor's counters, or a bus's and its sensors' (audited).
async function resetCounters(kind, name, messageHost) {
  const what = kind === "bus" ? "bus " + name + " and each of its sensors" : name;
  if (!await askConfirm("Reset the counters of " + what + " to zero?",
                        "The counts since start begin again from now, here, in /metrics and in the registers that serve them."))
    return;
  const path = (kind === "bus" ? "/api/buses/" : "/api/sensors/") + encodeURIComponent(name) + "/counters/reset";
  try {
    await api("POST", path, {});
    messageHost.textContent = "Counters of " + what + " reset.";
    messageHost.classList.remove("bad");
    messageHost.classList.add("ok");
  } catch (e) {
    messageHost.textContent = "Could not reset the counters: " + e.message;
    messageHost.classList.remove("ok");
    messageHost.classList.add("bad");
  }
}

function updateCard(card, s) {
  const p = card.parts;
  const [cls, label] = stateOf(s);
  card.root.className = "card " + cls;
  p.name.textContent = s.name;
  p.pill.textContent = label;
  p.meta.textContent = s.model + " \u00B7 " + (s.serial ? "S/N " + s.serial : "S/N not read yet") +
    (s.wrong_device ? ", configured S/N " + s.configured_serial : "");
  p.where.textContent = "unit " + s.unit_id + " \u00B7 bus " + s.bus + " \u00B7 address " + s.address;
  const x = degrees(s.x), y = degrees(s.y);
  const single = (s.y === null || s.y === undefined) && s.x !== null && s.x !== undefined;
  p.yAxis.style.visibility = p.y.style.visibility = single ? "hidden" : "";
  if (card.last !== null && (card.last.x !== x || card.last.y !== y))
    card.root.dataset.changes = String(Number(card.root.dataset.changes) + 1);
  card.last = {x, y};
  card.sensor = s;
  p.x.textContent = x;
  p.y.textContent = y;
  card.root.dataset.x = x;
  // The bubble shows the tilt's direction and size, held inside the face when off scale.
  const scale = gaugeScale(s.x, s.y);
  let gx = (s.x || 0) / scale, gy = (s.y || 0) / scale;
  const r = Math.hypot(gx, gy);
  if (r > 1) { gx /= r; gy /= r; }
  // Full scale puts the bubble against the rim (its centre at 0.8 of the face's radius).
  p.bubble.setAttribute("cx", (0.8 * gx).toFixed(3));
  p.bubble.setAttribute("cy", (-0.8 * gy).toFixed(3));
  p.bubble.style.visibility = s.x === null || s.x === undefined ? "hidden" : "";
  p.scale.textContent = "\u00B1" + scale + "\u00B0";
  p.age.textContent = age(s.age_ms);
  const rate = typeof s.polls_per_s === "number" ? s.polls_per_s
             : rateOf("sensor:" + s.name, (s.polls_ok || 0) + (s.polls_failed || 0));
  p.rate.textContent = perSecond(rate) + " polls/s";
  const [errors, bad] = errorsText(s);
  p.errors.textContent = errors;
  p.errors.className = "errors" + (bad ? " bad" : "");
  const words = ALARMS.filter(([bit]) => (s.alarms || 0) & bit).map(([, word]) => word);
  const alarmHtml = words.map((w) => '<span class="alarm">' + esc(w) + "</span>").join("");
  if (p.alarms.innerHTML !== alarmHtml) p.alarms.innerHTML = alarmHtml;
}

function renderSensors(list) {
  const host = $("sensors");
  const seen = new Set();
  for (const s of list) {
    seen.add(s.name);
    let card = cards.get(s.name);
    if (!card) { card = newCard(s); cards.set(s.name, card); }
    updateCard(card, s);
    host.appendChild(card.root);  // keeps the API's order; a no-op move when unchanged
  }
  for (const [name, card] of cards) if (!seen.has(name)) { card.root.remove(); cards.delete(name); }
  if (list.length === 0) host.innerHTML = '<div class="empty">No sensors configured.</div>';
  else host.querySelector(".empty")?.remove();
}

function renderBuses(list) {
  const host = $("buses");
  const seen = new Set();
  for (const b of list) {
    seen.add(b.name);
    let row = busRows.get(b.name);
    if (!row) {
      const root = document.createElement("div");
      root.className = "bus";
      root.innerHTML = '<span class="name"></span><span class="port muted"></span>' +
                       '<span class="protocol muted"></span><span class="rate num"></span>' +
                       '<span class="meter num"><span class="track"><span class="fill"></span></span><span class="use"></span></span>';
      const q = (sel) => root.querySelector(sel);
      row = {root, parts: {name: q(".name"), port: q(".port"), protocol: q(".protocol"),
                           rate: q(".rate"), fill: q(".fill"), use: q(".use")}};
      busRows.set(b.name, row);
    }
    const p = row.parts;
    p.name.textContent = b.name;
    p.port.textContent = b.port + " @ " + b.baud + " baud";
    p.protocol.textContent = b.protocol;
    const rate = typeof b.polls_per_s === "number" ? b.polls_per_s : rateOf("bus:" + b.name, b.polls || 0);
    p.rate.textContent = perSecond(rate) + " polls/s";
    if (typeof b.utilisation === "number") {
      const pct = Math.max(0, Math.min(1, b.utilisation)) * 100;
      p.fill.parentElement.hidden = false;
      p.fill.style.width = pct.toFixed(1) + "%";
      p.fill.className = "fill" + (pct >= 85 ? " high" : "");
      p.use.textContent = pct.toFixed(0) + "% of wire";
      p.use.className = "use";
    } else {
      p.fill.parentElement.hidden = true;
      p.use.textContent = "wire use not reported";
      p.use.className = "use absent";
    }
    host.appendChild(row.root);
  }
  for (const [name, row] of busRows) if (!seen.has(name)) { row.root.remove(); busRows.delete(name); }
}

function renderSummary(sensors) {
  const count = (cls) => sensors.filter((s) => stateOf(s)[0] === cls).length;
  const parts = ["<b>" + count("online") + "</b> of " + sensors.length + " online"];
  const stale = count("stale"), offline = count("offline");
  if (stale) parts.push("<b>" + stale + "</b> stale");
  if (offline) parts.push("<b>" + offline + "</b> offline");
  const wrong = count("wrong");
  if (wrong) parts.push("<b>" + wrong + "</b> wrong device");
  $("summary").innerHTML = parts.join(" \u00B7 ");
}

function setReachable(ok) {
  const body = document.body;
  if (ok) {
    unreachableSince = null;
    body.classList.remove("unreachable");
    body.dataset.state = "live";
    $("banner").hidden = true;
    return;
  }
  if (unreachableSince === null) unreachableSince = new Date();
  body.classList.add("unreachable");
  body.dataset.state = "unreachable";
  $("banner").hidden = false;
  $("banner").textContent = "Gateway unreachable since " + clock(unreachableSince) +
                            " \u2014 the values shown are from before then; retrying.";
}

// When something began, from Unix seconds: the time of day, and the date unless it is today.
function sinceText(seconds) {
  const date = new Date(seconds * 1000);
  const today = date.toDateString() === new Date().toDateString();
  return (today ? "" : date.toLocaleDateString() + " ") + clock(date);
}

// The gateway's role in a warm standby pair (/api/status "redundancy"); nothing without one.
function renderPair(state) {
  const el = $("pair");
  const pair = state.redundancy;
  if (!pair) { el.hidden = true; return; }
  const standby = state.role === "standby";
  const heard = pair.last_request_heard_ms;
  const what = standby
    ? "<b>Standby</b>: listening to the active gateway since " + esc(sinceText(pair.since)) + ", " +
      (heard === null ? "no request heard yet" : "last request heard " + heard + " ms ago") +
      " \u2014 the values shown are what it hears"
    : "<b>Active</b> since " + esc(sinceText(pair.since));
  const more = ["peer " + esc(pair.peer), "configured " + esc(pair.configured_role),
                pair.takeovers + " takeover" + (pair.takeovers === 1 ? "" : "s")];
  el.innerHTML = what + " <span class=\"muted\">(" + more.join(", ") + ")</span>";
  el.title = pair.reason;
  el.className = "pair " + (standby ? "standby" : "active");
  el.hidden = false;
}

// The gateway's clock (/api/status "clock"): every reading's time comes from it, so one that is
// not synchronised is said plainly (its readings are flagged: status bit 8).
function renderClock(state) {
  const c = state.clock;
  const el = $("clock");
  if (!c) { el.hidden = true; return; }
  el.textContent = c.synchronised
    ? "clock synchronised" + (c.error_ms === null ? "" : " \u00B1" + (c.error_ms < 10 ? c.error_ms.toFixed(1) : c.error_ms.toFixed(0)) + " ms")
    : "clock not synchronised: readings are flagged";
  el.title = c.synchronised ? "the system clock's maximum error, as the kernel estimates it"
                            : "NTP (chrony or systemd-timesyncd) has not synchronised the system clock";
  el.className = "clock num" + (c.synchronised ? "" : " unsynchronised");
  el.hidden = false;
}

let lastBuses = [];
let lastSensors = [];
let polls = 0;
async function poll() {
  if (document.body.dataset.state === "login") { setTimeout(poll, POLL_MS); return; }
  try {
    const withStatus = polls++ % STATUS_EVERY === 0;
    const [sensors, buses, state] = await Promise.all([
      getJson("/api/sensors"), getJson("/api/buses"), withStatus ? getJson("/api/status") : null]);
    renderSensors(sensors);
    renderBuses(buses);
    renderSummary(sensors);
    if (state) { renderPair(state); renderClock(state); }
    if (withStatus) refreshRecentEvents();
    lastBuses = buses;
    lastSensors = sensors;
    // renderScans: a panel for a bus the tab did not have yet (the tab opened before the first
    // poll, or a reload added it), then every bus's counters.
    if (currentTab === "buses") renderScans();
    if (settingsFor !== null && !$("detail").hidden) renderSensorCounters(sensors.find((x) => x.name === settingsFor));
    setReachable(true);
    document.body.dataset.updates = String(Number(document.body.dataset.updates) + 1);
    $("updated").textContent = "updated " + clock(new Date());
  } catch (e) {
    if (!(e instanceof LoggedOut)) setReachable(false);
  } finally {
    setTimeout(poll, POLL_MS);
  }
}

// ---- the history graph ----
// "10 min" is the recent ring (/history, a sample a second, redrawn every HISTORY_MS); a longer
// span is the long record (history.csv?from=&to=&points=), which the gateway merges into at most
// GRAPH_POINTS steps: each is drawn as its mean, in a band from its least to its greatest value,
// so a short spike still shows in a week. A sensor that reports a temperature has it as a
// dashed line on the right-hand scale.
const GRAPH_POINTS = 600;
const RECORD_REFRESH_MS = 60000;
let graphSpan = 0;  // 0: the recent ring; else milliseconds back from now

function niceStep(span, ticks) {
  const raw = span / ticks;
  const power = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 2.5, 5, 10]) if (raw <= m * power) return m * power;
  return 10 * power;
}

// The decimals a step's labels need: 0.25 needs two, 0.5 one.
function stepDecimals(step, most) {
  const power = Math.floor(Math.log10(step) + 1e-9);
  const quarter = Math.abs(step / Math.pow(10, power) - 2.5) < 1e-9 ? 1 : 0;
  return Math.max(0, Math.min(most, quarter - power));
}

function present(v) { return v !== null && v !== undefined && !Number.isNaN(v); }

// [lo, hi] of `values` with a margin, at least `least` wide.
function scaleOf(values, least) {
  let lo = Math.min(...values), hi = Math.max(...values);
  if (hi - lo < least) { const mid = (hi + lo) / 2; lo = mid - least / 2; hi = mid + least / 2; }
  const padding = (hi - lo) * 0.08;
  return [lo - padding, hi + padding];
}

// The path of `key` through the samples, lifted where it has no value; a point alone is a dot
// (a stroke of no length, drawn by its round cap).
function linePath(samples, key, px, py) {
  let d = "", pen = false;
  for (const s of samples) {
    if (!present(s[key])) { pen = false; continue; }
    d += (pen ? "L" : "M") + px(s.t).toFixed(1) + " " + py(s[key]).toFixed(1) + (pen ? "" : "h0");
    pen = true;
  }
  return d;
}

// The band between `lo` and `hi` through the samples: one closed shape per unbroken run.
function bandPath(samples, lo, hi, px, py) {
  let d = "", run = [];
  const close = () => {
    if (run.length > 1) {
      d += "M" + run.map((s) => px(s.t).toFixed(1) + " " + py(s[hi]).toFixed(1)).join("L");
      d += "L" + run.slice().reverse().map((s) => px(s.t).toFixed(1) + " " + py(s[lo]).toFixed(1)).join("L") + "Z";
    }
    run = [];
  };
  for (const s of samples) {
    if (present(s[lo]) && present(s[hi])) run.push(s); else close();
  }
  close();
  return d;
}

function timeLabel(t, span) {
  const d = new Date(t);
  if (span <= 86400000) return span > 3600000 ? pad(d.getHours()) + ":" + pad(d.getMinutes()) : clock(d);
  return pad(d.getMonth() + 1) + "-" + pad(d.getDate()) + (span <= 7 * 86400000 ? " " + pad(d.getHours()) + ":00" : "");
}

function drawGraph(samples, span) {
  const W = 900, H = 320, L = 62, T = 14, B = 34;
  const temperatures = samples.map((s) => s.temperature).filter(present);
  const R = temperatures.length > 0 ? 62 : 16;
  const angles = [];
  for (const s of samples) for (const k of ["x", "y", "xlo", "xhi", "ylo", "yhi"]) if (present(s[k])) angles.push(s[k]);
  if (angles.length === 0 && temperatures.length === 0)
    return '<div class="empty">' + (span
      ? "Nothing recorded in this range yet: the gateway writes a row of the long record each interval (1 minute by default)."
      : "No readings recorded yet: the gateway keeps one sample a period and the graph fills as they come.") + "</div>";
  const [lo, hi] = angles.length ? scaleOf(angles, 0.01) : [-1, 1];
  const t1 = span ? Date.now() : Math.max(samples[samples.length - 1].t, samples[0].t + 1000);
  const t0 = span ? t1 - span : samples[0].t;
  const px = (t) => L + (t - t0) * (W - L - R) / (t1 - t0);
  const py = (v) => T + (hi - v) * (H - T - B) / (hi - lo);
  let svg = '<svg class="graph" viewBox="0 0 ' + W + " " + H + '" role="img" aria-label="angles over time">';
  const step = niceStep(hi - lo, 5);
  const decimals = stepDecimals(step, 4);
  for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) {
    const y = py(v).toFixed(1);
    svg += '<line class="gridline" x1="' + L + '" x2="' + (W - R) + '" y1="' + y + '" y2="' + y + '"/>';
    svg += '<text class="label" x="' + (L - 8) + '" y="' + y + '" dy="4" text-anchor="end">' + v.toFixed(decimals) + "\u00B0</text>";
  }
  const tStep = [1, 2, 5, 10, 15, 30, 60, 120, 300, 600, 900, 1800, 3600, 7200, 10800, 21600, 43200, 86400, 172800, 432000]
                  .map((s) => s * 1000).find((s) => (t1 - t0) / s <= 7) || 604800000;
  for (let t = Math.ceil(t0 / tStep) * tStep; t <= t1; t += tStep) {
    const x = px(t).toFixed(1);
    svg += '<line class="gridline" x1="' + x + '" x2="' + x + '" y1="' + T + '" y2="' + (H - B) + '"/>';
    svg += '<text class="label" x="' + x + '" y="' + (H - B + 18) + '" text-anchor="middle">' + timeLabel(t, t1 - t0) + "</text>";
  }
  for (const axis of ["x", "y"]) {
    const band = bandPath(samples, axis + "lo", axis + "hi", px, py);
    if (band) svg += '<path class="band ' + axis + '" d="' + band + '"/>';
  }
  for (const axis of ["x", "y"]) {
    const d = linePath(samples, axis, px, py);
    if (d) svg += '<path class="line ' + axis + '" d="' + d + '"/>';
  }
  if (temperatures.length > 0) {
    const [tlo, thi] = scaleOf(temperatures, 1);
    const pt = (v) => T + (thi - v) * (H - T - B) / (thi - tlo);
    const tstep = niceStep(thi - tlo, 5);
    const tdecimals = stepDecimals(tstep, 2);
    for (let v = Math.ceil(tlo / tstep) * tstep; v <= thi; v += tstep)
      svg += '<text class="label temperature" x="' + (W - R + 8) + '" y="' + pt(v).toFixed(1) + '" dy="4">' + v.toFixed(tdecimals) + "\u00B0C</text>";
    svg += '<path class="line temperature" d="' + linePath(samples, "temperature", px, pt) + '"/>';
  }
  return svg + "</svg>";
}

// The long record's CSV (monitoring/history_csv.h) as graph samples: each row's mean, least and
// greatest value; the row's time is the start of its step.
function recordSamples(text) {
  const lines = text.trim().split(/\r?\n/);
  const head = lines.shift().split(",");
  const at = (name) => head.indexOf(name);
  const number = (cells, name) => { const v = cells[at(name)]; return v === undefined || v === "" ? null : Number(v); };
  return lines.map((line) => {
    const c = line.split(",");
    return {t: Date.parse(c[at("time")]), x: number(c, "x_mean"), y: number(c, "y_mean"),
            xlo: number(c, "x_min"), xhi: number(c, "x_max"), ylo: number(c, "y_min"), yhi: number(c, "y_max"),
            temperature: number(c, "temperature_mean")};
  });
}

function recordUrl(name, span, points) {
  const to = Date.now(), from = to - span;
  return "/api/sensors/" + encodeURIComponent(name) + "/history.csv?from=" + from + "&to=" + to +
    (points ? "&points=" + points : "");
}

async function graphSamples(name) {
  if (!graphSpan) return getJson("/api/sensors/" + encodeURIComponent(name) + "/history");
  return recordSamples(await getText(recordUrl(name, graphSpan, GRAPH_POINTS)));
}

function spanText(ms) {
  const minutes = ms / 60000;
  if (minutes < 2) return Math.round(minutes * 60) + " s";
  if (minutes < 120) return minutes.toFixed(0) + " min";
  if (minutes < 2880) return (minutes / 60).toFixed(0) + " h";
  return (minutes / 1440).toFixed(0) + " days";
}

async function refreshHistory() {
  if (openSensor === null) return;
  const name = openSensor, span = graphSpan;
  try {
    const samples = await graphSamples(name);
    if (openSensor !== name || graphSpan !== span) return;
    $("detail-graph").innerHTML = drawGraph(samples, span);
    $("detail-temperature-key").hidden = !samples.some((s) => present(s.temperature));
    if (span) {
      setCsvLink(name);  // the span up to now
      $("detail-range").textContent = samples.length + (samples.length === 1 ? " step" : " steps") +
        " of the long record over the last " + spanText(span);
    } else {
      const ms = samples.length > 1 ? samples[samples.length - 1].t - samples[0].t : 0;
      $("detail-range").textContent = samples.length + " samples" + (ms > 0 ? " over the last " + spanText(ms) : "");
    }
  } catch (e) {
    // The page's banner already says the gateway is away; keep the last graph.
  }
}

// The CSV link: the recent samples, or every row of the long record over the span shown.
function setCsvLink(name) {
  $("detail-csv").href = graphSpan ? recordUrl(name, graphSpan, 0)
                                   : "/api/sensors/" + encodeURIComponent(name) + "/history.csv";
  $("detail-csv").setAttribute("download", name + (graphSpan ? "-record.csv" : "-history.csv"));
}

function showSpan(span) {
  graphSpan = span;
  for (const b of document.querySelectorAll("#detail-zoom button"))
    b.setAttribute("aria-pressed", String(Number(b.dataset.span) === span));
  if (openSensor === null) return;
  setCsvLink(openSensor);
  $("detail-graph").innerHTML = '<div class="empty">Loading&hellip;</div>';
  refreshHistory();
  clearInterval(historyTimer);
  historyTimer = setInterval(refreshHistory, span ? RECORD_REFRESH_MS : HISTORY_MS);
}

// The sensor's bursts (docs/monitoring.md, "Bursts"), newest first, each a CSV download.
const BURSTS_SHOWN = 10;
async function loadBursts(name) {
  const base = "/api/sensors/" + encodeURIComponent(name) + "/bursts";
  let bursts = [];
  try { bursts = await getJson(base); } catch (e) { bursts = []; }
  if (openSensor !== name) return;
  $("detail-bursts").hidden = bursts.length === 0;
  $("detail-burst-list").innerHTML = bursts.slice(0, BURSTS_SHOWN).map((b) =>
    '<li><a href="' + base + "/" + encodeURIComponent(b.id) + '.csv" download="' +
    esc(name + "-burst-" + b.id + ".csv") + '">' + esc(sinceText(b.unix_ms / 1000)) + "</a> " +
    '<span class="muted">' + Math.max(1, Math.round(b.bytes / 1024)) + " KB</span></li>").join("") +
    (bursts.length > BURSTS_SHOWN ? '<li class="muted">and ' + (bursts.length - BURSTS_SHOWN) + " older</li>" : "");
}

function openHistory(name) {
  if (document.body.classList.contains("unreachable")) return;
  openSensor = name;
  const card = cards.get(name);
  $("detail-name").textContent = name;
  $("detail-sub").textContent = card ? card.parts.meta.textContent + " \u00B7 " + card.parts.where.textContent : "";
  $("detail").hidden = false;
  $("detail-bursts").hidden = true;
  showSpan(0);
  loadBursts(name);
  $("detail-console").hidden = !session.accounts;
  if (session.accounts) loadSensorConsole(name);
  $("detail-close").focus();
}

function closeHistory() {
  openSensor = null;
  settingsFor = null;
  clearInterval(historyTimer);
  $("detail").hidden = true;
}

for (const b of document.querySelectorAll("#detail-zoom button"))
  b.addEventListener("click", () => showSpan(Number(b.dataset.span)));
$("detail-close").addEventListener("click", closeHistory);
$("detail").addEventListener("click", (e) => { if (e.target === $("detail")) closeHistory(); });
document.addEventListener("keydown", (e) => {
  if (e.key !== "Escape") return;
  if (!$("confirm").hidden) answerConfirm(false); else closeHistory();
});
// ---- the console: accounts, roles and actions (only when /api/session says accounts) ----
const ACTION_TIMEOUT_MS = 30000;   // a setting waits for the sensor's ACK; the gateway answers 504 itself
const SCAN_POLL_MS = 500;
const RANKS = {viewer: 0, operator: 1, admin: 2};
let session = {accounts: false, user: null, role: null, csrf: null};
let currentTab = "sensors";
let servedConfig = null;           // the text the gateway serves, for the diff

function may(role) {
  return session.accounts && (RANKS[session.role] ?? -1) >= (RANKS[role] ?? 99);
}

// Disables every control marked data-needs="ROLE" the user's role may not use, saying why, and
// hides the tabs the role cannot open and what is marked data-hide (the traffic view).
function applyRole(root = document) {
  for (const el of root.querySelectorAll("[data-needs]")) {
    const allowed = may(el.dataset.needs);
    if (el.classList.contains("tab") || "hide" in el.dataset) { el.hidden = !allowed; continue; }
    el.disabled = !allowed;
    if (allowed) el.removeAttribute("title");
    else el.title = "needs the " + el.dataset.needs + " role (you are " + (session.role || "not logged in") + ")";
  }
}

class ApiError extends Error {
  constructor(status, body) {
    super((body && body.error) || ("the gateway answered " + status));
    this.status = status;
    this.body = body || {};
  }
}

// Every console request: JSON in and out; a change carries the session's CSRF token.
async function api(method, path, body) {
  const headers = {};
  const init = {method, headers, cache: "no-store", credentials: "same-origin"};
  if (method !== "GET") {
    headers["Content-Type"] = "application/json";
    headers["X-CSRF-Token"] = session.csrf || "";
    init.body = JSON.stringify(body === undefined ? {} : body);
  }
  const abort = new AbortController();
  const timer = setTimeout(() => abort.abort(), ACTION_TIMEOUT_MS);
  init.signal = abort.signal;
  let reply;
  try {
    reply = await fetch(path, init);
  } catch (e) {
    throw new ApiError(0, {error: "the gateway did not answer"});
  } finally {
    clearTimeout(timer);
  }
  let data = null;
  try { data = await reply.json(); } catch (e) { data = null; }
  if (reply.status === 401 && path !== "/api/login") {
    showLogin("Your session ended: log in again.");
    throw new ApiError(401, data);
  }
  if (!reply.ok) throw new ApiError(reply.status, data);
  return data;
}

function say(id, text, kind) {
  const el = $(id);
  el.textContent = text;
  el.className = "message" + (kind ? " " + kind : "");
}

// ---- session and login ----
function setSession(data) {
  session = {accounts: true, user: data.user, role: data.role, csrf: data.csrf};
  document.body.dataset.role = data.role;
  $("brand-sub").textContent = "console";
  document.title = "tiltgate console";
  $("who-name").textContent = data.user;
  $("who-role").textContent = data.role;
  $("who").hidden = false;
  $("tabs").hidden = false;
  $("login").hidden = true;
  if (document.body.dataset.state === "login") document.body.dataset.state = "connecting";
  applyRole();
  showTab(may(tabNeeds(currentTab)) ? currentTab : "sensors");
}

function tabNeeds(tab) {
  return document.querySelector('.tab[data-tab="' + tab + '"]').dataset.needs || "viewer";
}

function showLogin(message) {
  session = {accounts: true, user: null, role: null, csrf: null};
  delete document.body.dataset.role;
  closeHistory();
  answerConfirm(false);
  document.body.dataset.state = "login";
  document.body.classList.remove("unreachable");
  $("banner").hidden = true;
  $("brand-sub").textContent = "console";
  document.title = "tiltgate console";
  $("who").hidden = true;
  $("tabs").hidden = true;
  for (const main of document.querySelectorAll("main")) main.hidden = true;
  // Nothing a previous user loaded stays on the page.
  $("editor").value = "";
  servedConfig = null;
  clearTraffic();   // traffic_view.js
  document.querySelector("#audit-table tbody").innerHTML = "";
  $("login").hidden = false;
  say("login-message", message || "", "bad");
  $("login-password").value = "";
  $(($("login-user").value ? "login-password" : "login-user")).focus();
}

async function logIn(event) {
  event.preventDefault();
  say("login-message", "");
  $("login-submit").disabled = true;
  try {
    const data = await api("POST", "/api/login",
                           {user: $("login-user").value, password: $("login-password").value});
    $("login-password").value = "";
    setSession(data);
  } catch (e) {
    if (e.status === 429) {
      const wait = e.body.retry_after_s;
      say("login-message", "Too many failed logins: try again in " +
          (typeof wait === "number" ? Math.ceil(wait) + " s" : "a while") + ".", "bad");
    } else if (e.status === 403) {
      say("login-message", (e.body.error || "Logins from another machine need HTTPS.") +
          " Open the gateway's address with https in front.", "bad");
    } else if (e.status === 401) {
      say("login-message", e.body.error || "Wrong user name or password.", "bad");
    } else {
      say("login-message", e.message, "bad");
    }
  } finally {
    $("login-submit").disabled = false;
  }
}

async function logOut() {
  try { await api("POST", "/api/logout"); } catch (e) { /* gone already: the form either way */ }
  showLogin("Logged out.");
  say("login-message", "Logged out.", "ok");
}

// ---- tabs ----
function showTab(tab) {
  currentTab = tab;
  for (const button of document.querySelectorAll(".tab"))
    button.setAttribute("aria-selected", String(button.dataset.tab === tab));
  for (const main of document.querySelectorAll("main")) main.hidden = main.id !== "tab-" + tab;
  if (tab === "buses") renderScans();
  if (tab === "raw") fillRawBuses();
  if (tab === "config" && servedConfig === null) loadConfig();
  if (tab === "audit") loadAudit();
  if (tab === "events") loadEvents();
}

// ---- a sensor: identity, settings, changes ----
let settingsFor = null;

async function loadSensorConsole(name, keepMessage) {
  settingsFor = name;
  $("detail-identity").innerHTML = "";
  document.querySelector("#detail-settings tbody").innerHTML =
    '<tr><td colspan="4" class="empty">Reading the settings from the sensor&hellip;</td></tr>';
  if (!keepMessage) say("detail-message", "");
  say("baseline-message", "");
  $("detail-baseline").textContent = "";
  const path = "/api/sensors/" + encodeURIComponent(name);
  try {
    const [sensor, settings] = await Promise.all([api("GET", path), api("GET", path + "/settings")]);
    if (settingsFor !== name) return;
    renderIdentity(sensor);
    renderSensorCounters(sensor);
    renderSettings(name, sensor, settings.settings || []);
  } catch (e) {
    if (settingsFor === name) say("detail-message", "Could not read the settings: " + e.message, "bad");
  }
  loadBaseline(name);
}

// ---- a sensor's baseline (docs/monitoring.md, "Baseline and displacement") ----
function baselineText(b) {
  const angles = "X " + degrees(b.x) + ", Y " + degrees(b.y);
  if (!b.stored) return angles + " \u2014 the configuration's";
  return angles + " \u2014 set by " + b.by + " at " + sinceText(b.unix_ms / 1000);
}

async function loadBaseline(name) {
  try {
    const b = await api("GET", "/api/sensors/" + encodeURIComponent(name) + "/baseline");
    if (settingsFor === name) $("detail-baseline").textContent = baselineText(b);
  } catch (e) {
    if (settingsFor === name) $("detail-baseline").textContent = "not known: " + e.message;
  }
}

async function changeBaseline(set) {
  const name = settingsFor;
  if (name === null) return;
  const asked = set === "current"
    ? "Set the baseline of " + name + " to its current reading?"
    : "Set the baseline of " + name + " back to the configuration's?";
  if (!await askConfirm(asked, "Every angle from the baseline, the displacement and its alarms are measured from it. The change is recorded in the audit trail and as an event."))
    return;
  try {
    const b = await api("POST", "/api/sensors/" + encodeURIComponent(name) + "/baseline", {set});
    if (settingsFor !== name) return;
    $("detail-baseline").textContent = baselineText(b);
    say("baseline-message", set === "current" ? "Baseline set to the current reading." : "Baseline back to the configuration's.", "ok");
  } catch (e) {
    say("baseline-message", "Could not change the baseline: " + e.message, "bad");
  }
}

function renderIdentity(s) {
  const rows = [["Model", s.model], ["Serial", s.serial || "not read yet"],
                ["Firmware", s.firmware || "not read"], ["Bus", s.bus], ["Address", s.address],
                ["Modbus unit", s.unit_id]];
  if (s.wrong_device) rows.push(["Configured serial", s.configured_serial]);
  $("detail-identity").innerHTML = rows.filter(([, v]) => v !== undefined && v !== null && v !== "")
    .map(([k, v]) => "<dt>" + esc(k) + "</dt><dd>" + esc(v) + "</dd>").join("");
}

// The open sensor's counters, from the list the page polls.
function renderSensorCounters(s) {
  const host = $("detail-counters");
  if (!s || !host) return;
  const extra = [["polls that gave a reading", s.polls_ok], ["slowest reply (ms)", s.slowest_reply_ms]];
  const html = countersHtml(Object.assign({polls_failed: s.polls_failed}, s.failures), s.failures_10min, extra);
  if (host.innerHTML !== html) host.innerHTML = html;
}

function valueText(v) { return v === null || v === undefined ? "unknown" : String(v); }

// Where the value shown comes from: the family reads it back, or it is what was last written.
function valueSource(setting) {
  return setting.read_back ? "read from the sensor" : "last written through this gateway";
}

// A setting's row: its label (the key a map file writes small beneath it), its value and where
// that comes from, its range, and its change: a command's actions as buttons named by what they
// do, a one-value setting as its button, any other as a field and Set.
function renderSettings(name, sensor, settings) {
  const body = document.querySelector("#detail-settings tbody");
  body.innerHTML = "";
  if (settings.length === 0)
    body.innerHTML = '<tr><td colspan="4" class="empty">This sensor\'s map names no settings.</td></tr>';
  for (const setting of settings) {
    const row = document.createElement("tr");
    row.dataset.setting = setting.name;
    const units = setting.units ? " " + setting.units : "";
    const actions = setting.actions || [];
    const oneValue = actions.length === 0 && setting.min === setting.max;
    row.innerHTML = '<td><b></b><div class="sub"><code class="key"></code></div><div class="sub what"></div></td>' +
                    '<td class="num value-cell"><span class="value"></span><div class="sub source"></div></td>' +
                    '<td class="num range"></td><td class="change"></td>';
    row.querySelector("b").textContent = setting.label || setting.name;
    row.querySelector(".key").textContent = setting.name;
    row.querySelector(".what").textContent = setting.description || "";
    // A command is done, not kept: no value to show.
    row.querySelector(".value").textContent = actions.length ? "" :
      valueText(setting.value) + (setting.value === null ? "" : units);
    if (actions.length === 0) row.querySelector(".source").textContent = valueSource(setting);
    row.querySelector(".value-cell").title = valueSource(setting);
    row.querySelector(".range").textContent = actions.length || oneValue ? "" : setting.min + " \u2026 " + setting.max + units;
    const cell = row.querySelector(".change");
    const addButton = (text, needs, danger, click) => {
      const button = document.createElement("button");
      button.type = "button";
      button.className = "button" + (danger ? " danger" : "");
      button.dataset.needs = needs;
      button.dataset.action = "set";
      button.textContent = text;
      button.addEventListener("click", click);
      cell.appendChild(button);
      return button;
    };
    if (actions.length) {
      for (const action of actions)
        addButton(action.name, action.role || "admin", action.role !== "operator",
                  () => changeSetting(name, sensor.bus, setting, action.value, null, action))
          .dataset.value = action.value;
    } else if (oneValue) {
      addButton(setting.label || setting.name, setting.role || "admin", true,
                () => changeSetting(name, sensor.bus, setting, setting.min, null));
    } else {
      const input = document.createElement("input");
      input.type = "number";
      input.min = setting.min;
      input.max = setting.max;
      input.step = "any";
      input.inputMode = "decimal";
      input.dataset.needs = setting.role || "admin";
      if (setting.value !== null && setting.value !== undefined) input.value = setting.value;
      input.setAttribute("aria-label", "new " + (setting.label || setting.name));
      cell.appendChild(input);
      addButton("Set", input.dataset.needs, false,
                () => changeSetting(name, sensor.bus, setting, Number(input.value), input));
    }
    body.appendChild(row);
  }
  applyRole($("detail-settings"));
}

// Writes `value` to the setting once the user agrees: to an action's question, or to one that
// names the setting, the sensor and the change.
async function changeSetting(name, bus, setting, value, input, action) {
  const label = setting.label || setting.name;
  if (input && (input.value === "" || !Number.isFinite(value))) {
    say("detail-message", "Enter a number for " + label + ".", "bad");
    return;
  }
  const where = (bus ? bus + "/" : "") + name;
  const what = action ? action.name : label;
  const question = action ? action.confirm
    : setting.min === setting.max
    ? "Set " + label + " (" + setting.name + ") of " + where + " (writes " + value + ")?"
    : "Set " + label + " (" + setting.name + ") of " + where + " from " + valueText(setting.value) + " to " + value + "?";
  if (!await askConfirm(question)) return;
  say("detail-message", what + ": waiting for the sensor\u2026");
  try {
    const r = await api("POST", "/api/sensors/" + encodeURIComponent(name) + "/settings",
                        {setting: setting.name, value});
    say("detail-message", action ? what + " on " + where + ": done (" + r.result + ")"
        : label + " of " + where + ": " + valueText(r.old) + " \u2192 " + valueText(r.value) + " (" + r.result + ")", "ok");
    document.body.dataset.lastResult = r.result;
  } catch (e) {
    const result = e.body.result ? " (" + e.body.result + ")" : "";
    const why = e.status === 409 ? "the sensor refused" : e.status === 504 ? "no answer from the sensor"
              : e.status === 403 ? "your role may not" : "refused";
    say("detail-message", what + " on " + where + ": " + why + ": " + e.message + result, "bad");
    document.body.dataset.lastResult = e.body.result || "error " + e.status;
    if (e.status === 401) return;
  }
  if (settingsFor === name) loadSensorConsole(name, true);
}

// ---- the confirmation dialog (a page's own: window.confirm is no use on some phones) ----
let confirmAnswer = null;
function askConfirm(text, detail) {
  $("confirm-text").textContent = text;
  $("confirm-detail").hidden = !detail;
  $("confirm-detail").innerHTML = detail || "";
  $("confirm").hidden = false;
  $("confirm-ok").focus();
  return new Promise((resolve) => { confirmAnswer = resolve; });
}
function answerConfirm(yes) {
  $("confirm").hidden = true;
  if (confirmAnswer) { const resolve = confirmAnswer; confirmAnswer = null; resolve(yes); }
}

// ---- buses: scan ----
const scanPanels = new Map();   // bus name -> {root, timer}

function renderScans() {
  const host = $("scans");
  if (lastBuses.length === 0) { host.innerHTML = '<div class="empty">No buses yet.</div>'; return; }
  host.querySelector(".empty")?.remove();
  for (const b of lastBuses) {
    if (scanPanels.has(b.name)) continue;
    const root = document.createElement("form");
    root.className = "box";
    root.dataset.bus = b.name;
    root.innerHTML =
      '<h3></h3><div class="sub port"></div>' +
      '<p class="hint" role="status" hidden></p>' +
      '<div class="scroll bus-counters"></div>' +
      '<div class="scroll line-health"></div>' +
      '<div class="row"><button class="button reset" type="button" data-needs="admin">Reset counters</button>' +
      '<div class="counters-message" role="status"></div></div>' +
      '<div class="row gap-above">' +
      '<label class="field">From address <input class="from" type="number" min="0" max="255" value="1" inputmode="numeric"></label>' +
      '<label class="field">To address <input class="to" type="number" min="0" max="255" value="32" inputmode="numeric"></label>' +
      '<button class="button primary scan" type="submit" data-needs="admin">Scan</button></div>' +
      '<div class="progress" hidden><span></span></div><div class="message"></div>' +
      '<pre class="output" hidden></pre><div class="scroll found"></div>';
    root.querySelector("h3").textContent = b.name;
    root.querySelector(".port").textContent = b.port + " @ " + b.baud + " baud \u00B7 " + b.protocol;
    root.addEventListener("submit", (e) => { e.preventDefault(); startScan(b.name); });
    root.querySelector(".reset").addEventListener("click", () =>
      resetCounters("bus", b.name, root.querySelector(".counters-message")));
    addTrafficView(root, b.name);   // traffic_view.js
    host.appendChild(root);
    scanPanels.set(b.name, {root, timer: null});
    applyRole(root);
    pollScan(b.name, false);   // shows a scan already running, or the last one's results
  }
  renderBusCounters();
}

// Each bus's counters on the Buses tab, from the list the page polls.
function renderBusCounters() {
  for (const b of lastBuses) {
    const panel = scanPanels.get(b.name);
    if (!panel) continue;
    const extra = [["polls", b.polls], ["writes", b.writes], ["forwarded requests", b.forwarded],
                   ["loop restarts", b.restarts || 0], ["replies held by this machine", b.machine_held],
                   ["attempts given up, overloaded", b.overloaded]];
    const html = countersHtml(b.failures, b.failures_10min, extra);
    const host = panel.root.querySelector(".bus-counters");
    if (host.innerHTML !== html) host.innerHTML = html;
    const hint = panel.root.querySelector(".hint");
    hint.hidden = !b.hint;
    if (hint.textContent !== (b.hint || "")) hint.textContent = b.hint || "";
    const health = lineHealthHtml(b, lastSensors.filter((s) => s.bus === b.name));
    const table = panel.root.querySelector(".line-health");
    if (table.innerHTML !== health) table.innerHTML = health;
  }
}

// Each sensor's exchanges on the bus, attempt by attempt (docs/diagnostics.md), one row each,
// the bus's total last: what a technician reads at a glance. A cell is red where a device
// failed to answer or answered garbled.
function lineHealthHtml(bus, sensors) {
  const columns = [["requests", "Requests"], ["replies", "Replies"], ["no_reply", "No reply"],
                   ["garbled", "Garbled"], ["naks", "NAK"], ["busy", "Busy"],
                   ["bytes_out", "Bytes out"], ["bytes_in", "Bytes in"]];
  const bad = new Set(["no_reply", "garbled", "naks", "busy"]);
  const row = (name, address, e, late) => "<tr><td>" + esc(name) + '</td><td class="num">' + esc(address) +
    "</td>" + columns.map(([key]) => '<td class="num' + (bad.has(key) && e[key] > 0 ? " bad" : "") + '">' +
    esc(e[key] || 0) + "</td>").join("") + '<td class="num' + (late > 0 ? " bad" : "") + '">' + esc(late) + "</td></tr>";
  const rows = sensors.map((s) => row(s.name, s.address, s.exchanges || {}, s.failures ? s.failures.late_reply : 0));
  if (bus.exchanges) rows.push(row("all", "\u2013", bus.exchanges, bus.failures ? bus.failures.late_reply : 0));
  return '<table class="list counters line"><thead><tr><th>Sensor</th><th>Address</th>' +
         columns.map(([, word]) => "<th>" + esc(word) + "</th>").join("") + "<th>Late</th></tr></thead><tbody>" +
         rows.join("") + "</tbody></table>" +
         '<div class="sub">Stray bytes between frames: ' + esc(bus.stray_bytes || 0) + "</div>";
}

async function startScan(bus) {
  const panel = scanPanels.get(bus);
  const from = Number(panel.root.querySelector(".from").value);
  const to = Number(panel.root.querySelector(".to").value);
  const message = panel.root.querySelector(".message");
  try {
    await api("POST", "/api/buses/" + encodeURIComponent(bus) + "/scan", {from, to});
    message.textContent = "Scanning " + from + " to " + to + "\u2026";
    message.className = "message";
    pollScan(bus, true);
  } catch (e) {
    message.textContent = (e.status === 409 ? "A scan is running already: " : "") + e.message;
    message.className = "message bad";
    if (e.status === 409) pollScan(bus, true);
  }
}

async function pollScan(bus, started) {
  const panel = scanPanels.get(bus);
  if (!panel) return;
  clearTimeout(panel.timer);
  let state;
  try {
    state = await api("GET", "/api/buses/" + encodeURIComponent(bus) + "/scan");
  } catch (e) {
    if (started) panel.timer = setTimeout(() => pollScan(bus, true), SCAN_POLL_MS * 4);
    return;
  }
  renderScan(bus, state);
  if (state.running && currentTab === "buses" && session.role)
    panel.timer = setTimeout(() => pollScan(bus, true), SCAN_POLL_MS);
}

function renderScan(bus, state) {
  const root = scanPanels.get(bus).root;
  const progress = root.querySelector(".progress");
  const message = root.querySelector(".message");
  const running = !!state.running;
  const fraction = Math.max(0, Math.min(1, Number(state.progress) || 0));
  progress.hidden = !running && !state.output && !(state.found || []).length;
  progress.firstElementChild.style.width = (fraction * 100).toFixed(1) + "%";
  root.dataset.running = String(running);
  root.querySelector(".scan").disabled = running || !may("admin");
  if (running) {
    message.textContent = "Scanning\u2026 " + Math.round(fraction * 100) + "%";
    message.className = "message";
  } else if (state.error) {
    message.textContent = "The scan failed: " + state.error;
    message.className = "message bad";
  } else if (state.output || (state.found || []).length) {
    message.textContent = "Scan finished: " + (state.found || []).length + " found.";
    message.className = "message ok";
  }
  const output = root.querySelector(".output");
  output.hidden = !state.output;
  if (output.textContent !== (state.output || "")) {
    output.textContent = state.output || "";
    output.scrollTop = output.scrollHeight;
  }
  const found = state.found || [];
  const host = root.querySelector(".found");
  if (found.length === 0) { host.innerHTML = ""; return; }
  host.innerHTML = '<table class="list"><thead><tr><th>Address</th><th>Model</th><th>Serial</th>' +
                   "<th>Firmware</th><th></th></tr></thead><tbody></tbody></table>";
  const tbody = host.querySelector("tbody");
  for (const f of found) {
    const row = document.createElement("tr");
    row.innerHTML = '<td class="num"></td><td></td><td></td><td></td><td></td>';
    [f.address, f.model, f.serial, f.firmware].forEach((v, i) => { row.children[i].textContent = valueText(v); });
    // The gateway marks a device the served configuration has (docs/web-console.md, "The API"):
    // nothing to add.
    if (f.configured_as) {
      row.children[4].textContent = "already configured as " + f.configured_as;
      row.children[4].className = "configured";
      tbody.appendChild(row);
      continue;
    }
    const add = document.createElement("button");
    add.type = "button";
    add.className = "button";
    add.textContent = "Add to the configuration";
    add.dataset.needs = "admin";
    add.addEventListener("click", () => addScannedSensor(f.config || ""));
    row.children[4].appendChild(add);
    tbody.appendChild(row);
  }
  applyRole(host);
}

// ---- raw frames ----
function fillRawBuses() {
  const select = $("raw-bus");
  const names = lastBuses.map((b) => b.name);
  if ([...select.options].map((o) => o.value).join("\n") === names.join("\n")) return;
  const chosen = select.value;
  select.innerHTML = names.map((n) => "<option>" + esc(n) + "</option>").join("");
  if (names.includes(chosen)) select.value = chosen;
}

function spacedHex(hex) {
  return (hex || "").replace(/\s+/g, "").replace(/(..)(?=.)/g, "$1 ").toUpperCase();
}

async function sendRaw(event) {
  event.preventDefault();
  const bus = $("raw-bus").value;
  if (!bus) { say("raw-message", "No bus to send on.", "bad"); return; }
  say("raw-message", "Sending\u2026");
  try {
    const r = await api("POST", "/api/buses/" + encodeURIComponent(bus) + "/raw", {
      address: Number($("raw-address").value), function: Number($("raw-function").value),
      data: $("raw-data").value.trim()});
    $("raw-result").hidden = false;
    $("raw-sent").textContent = spacedHex(r.sent);
    $("raw-received").textContent = r.received === null || r.received === undefined ? "no reply" : spacedHex(r.received);
    $("raw-verdict").textContent = r.verdict || "";
    $("raw-decoded").textContent = r.decoded || r.output || "";
    if (r.error) say("raw-message", r.error, "bad"); else say("raw-message", "Answered.", "ok");
  } catch (e) {
    say("raw-message", e.message, "bad");
  }
}

// ---- configuration: view, edit, check, diff, apply, download ----
async function loadConfig() {
  try {
    const c = await api("GET", "/api/config");
    servedConfig = c.text;
    $("editor").value = c.text;
    const loaded = typeof c.loaded_at === "number" ? new Date(c.loaded_at).toLocaleString() : c.loaded_at;
    $("config-where").textContent = c.path + (loaded ? " \u00B7 loaded " + loaded : "");
    $("config-errors").innerHTML = "";
    $("config-diff-out").hidden = true;
    say("config-message", "");
    showPending(c.pending, null);
    refreshTables();  // config_forms.js
  } catch (e) {
    say("config-message", "Could not read the configuration: " + e.message, "bad");
  }
}

// ---- the confirmation window of an apply: a countdown, and Confirm where the new file serves ----
const CONFIRM_S = 120;             // PUT /api/config's confirm_s
let pendingTimer = null;

// The console's address as the applied file serves it, or null when it is this page's.
function newConsoleUrl(console_) {
  if (!console_) return null;
  const wildcard = console_.listen === "0.0.0.0" || console_.listen === "::";
  const protocol = console_.https ? "https:" : "http:";
  const port = String(console_.port);
  const herePort = location.port || (location.protocol === "https:" ? "443" : "80");
  if (protocol === location.protocol && port === herePort &&
      (wildcard || console_.listen === location.hostname.replace(/^\[|\]$/g, ""))) return null;
  const host = wildcard ? location.hostname : (console_.listen.includes(":") ? "[" + console_.listen + "]" : console_.listen);
  return protocol + "//" + host + ":" + port + "/";
}

// `pending`: GET /api/config's (or the apply's) window; `console_`: where the applied file serves
// the console (null: here).
function showPending(pending, console_) {
  clearInterval(pendingTimer);
  $("config-pending").hidden = !pending;
  if (!pending) return;
  const end = Date.now() + pending.seconds_left * 1000;
  const url = console_ && console_.enabled === false ? "" : newConsoleUrl(console_);
  $("config-confirm").hidden = url !== null;
  $("config-confirm-link").hidden = !url;
  if (url) $("config-confirm-link").href = url;
  const tick = () => {
    const left = Math.max(0, Math.round((end - Date.now()) / 1000));
    const where = url === "" ? "The applied file turns the console off: nobody can confirm it, so"
                : url ? "Confirm at " + url + " (log in there), or"
                : "Confirm once you have checked the gateway, or";
    $("config-pending-text").textContent = where + " the previous file comes back in " + left + " s.";
    if (left === 0) { clearInterval(pendingTimer); setTimeout(loadConfig, 3000); }
  };
  tick();
  pendingTimer = setInterval(tick, 1000);
}

async function confirmConfig() {
  try {
    await api("POST", "/api/config/confirm");
    showPending(null);
    say("config-message", "Confirmed: the applied configuration stays.", "ok");
  } catch (e) {
    say("config-message", "Not confirmed: " + e.message, "bad");
  }
}

function showConfigErrors(errors) {
  const list = $("config-errors");
  list.innerHTML = "";
  for (const err of errors || []) {
    const item = document.createElement("li");
    const button = document.createElement("button");
    button.type = "button";
    // A problem of the machine (a user, an address, a certificate) has no line.
    button.textContent = err.line ? "line " + err.line + ":" + err.column + ": " + err.message
                                  : err.text;
    if (err.line) button.addEventListener("click", () => jumpToLine(err.line, err.column));
    item.appendChild(button);
    list.appendChild(item);
  }
}

function jumpToLine(line, column) {
  const editor = $("editor");
  const lines = editor.value.split("\n");
  let at = 0;
  for (let i = 0; i < Math.min(line - 1, lines.length); i++) at += lines[i].length + 1;
  const length = (lines[line - 1] || "").length;
  editor.focus();
  editor.setSelectionRange(at + Math.max(0, Math.min((column || 1) - 1, length)), at + length);
  const lineHeight = parseFloat(getComputedStyle(editor).lineHeight) || 17;
  editor.scrollTop = Math.max(0, (line - 4) * lineHeight);
}

async function checkConfig() {
  say("config-message", "Checking\u2026");
  try {
    const r = await api("POST", "/api/config/check", {text: $("editor").value});
    showConfigErrors(r.errors);
    if (r.ok) say("config-message", "The configuration is valid.", "ok");
    else say("config-message", (r.errors || []).length + " problem(s): click one to go to its line.", "bad");
    return r.ok;
  } catch (e) {
    say("config-message", e.message, "bad");
    return false;
  }
}

// A line diff by longest common subsequence, after taking off the common head and tail; a
// middle too big for the table is shown as all removed and all added.
function lineDiff(before, after) {
  const a = before.split("\n"), b = after.split("\n");
  let head = 0;
  while (head < a.length && head < b.length && a[head] === b[head]) head++;
  let tail = 0;
  while (tail < a.length - head && tail < b.length - head &&
         a[a.length - 1 - tail] === b[b.length - 1 - tail]) tail++;
  const x = a.slice(head, a.length - tail), y = b.slice(head, b.length - tail);
  const ops = [];
  for (let i = 0; i < head; i++) ops.push([" ", a[i], i + 1]);
  if (x.length * y.length > 4000000) {
    x.forEach((l, i) => ops.push(["-", l, head + i + 1]));
    y.forEach((l) => ops.push(["+", l, null]));
  } else {
    const n = x.length, m = y.length, w = m + 1;
    const lcs = new Uint32Array((n + 1) * w);
    for (let i = n - 1; i >= 0; i--)
      for (let j = m - 1; j >= 0; j--)
        lcs[i * w + j] = x[i] === y[j] ? lcs[(i + 1) * w + j + 1] + 1
                                       : Math.max(lcs[(i + 1) * w + j], lcs[i * w + j + 1]);
    let i = 0, j = 0;
    while (i < n || j < m) {
      if (i < n && j < m && x[i] === y[j]) { ops.push([" ", x[i], head + i + 1]); i++; j++; }
      else if (i < n && (j === m || lcs[(i + 1) * w + j] >= lcs[i * w + j + 1])) { ops.push(["-", x[i], head + i + 1]); i++; }
      else { ops.push(["+", y[j], null]); j++; }
    }
  }
  for (let i = a.length - tail; i < a.length; i++) ops.push([" ", a[i], i + 1]);
  return ops;
}

// The diff as HTML: changed lines with two lines of context, each hunk headed by its line.
function diffHtml(ops) {
  const CONTEXT = 2;
  const keep = ops.map(() => false);
  ops.forEach(([op], i) => {
    if (op === " ") return;
    for (let k = Math.max(0, i - CONTEXT); k <= Math.min(ops.length - 1, i + CONTEXT); k++) keep[k] = true;
  });
  let html = "", previous = -2, added = 0, removed = 0;
  ops.forEach(([op, text, line], i) => {
    if (op === "+") added++;
    if (op === "-") removed++;
    if (!keep[i]) return;
    if (i !== previous + 1) {
      const at = ops.slice(i).find((o) => o[2] !== null);
      html += '<span class="hunk">@@ line ' + (at ? at[2] : "end") + " @@</span>";
    }
    previous = i;
    const cls = op === "+" ? "add" : op === "-" ? "del" : "";
    const line_ = esc(op + " " + text);
    html += cls ? '<span class="' + cls + '">' + line_ + "</span>" : line_ + "\n";
  });
  return {html, added, removed};
}

function showDiff() {
  if (servedConfig === null) return null;
  const d = diffHtml(lineDiff(servedConfig, $("editor").value));
  const out = $("config-diff-out");
  out.hidden = false;
  out.innerHTML = d.added + d.removed === 0 ? "No changes from the served file." : d.html;
  out.dataset.added = String(d.added);
  out.dataset.removed = String(d.removed);
  return d;
}

async function applyConfig() {
  const d = showDiff();
  if (!d) return;
  if (d.added + d.removed === 0) { say("config-message", "Nothing to apply: the text is the served file."); return; }
  if (!await askConfirm("Apply this configuration to the gateway (+" + d.added + " \u2212" + d.removed +
                        " lines)? It is written, the previous file kept, and reloaded; unless you " +
                        "confirm it within " + CONFIRM_S + " s, the previous file comes back.", d.html)) return;
  say("config-message", "Applying\u2026");
  try {
    const r = await api("PUT", "/api/config", {text: $("editor").value, confirm_s: CONFIRM_S});
    await loadConfig();
    showPending({seconds_left: r.confirm_s}, r.console);
    say("config-message", "Applied and reloaded; the previous file is kept as " + r.previous + ".", "ok");
  } catch (e) {
    if (e.status === 422) {
      showConfigErrors(e.body.errors);
      say("config-message", "Not applied, nothing changed: " + (e.body.errors || []).length +
          " problem(s); click one to go to its line.", "bad");
    } else {
      say("config-message", "Not applied: " + e.message, "bad");
    }
  }
}

// ---- events (docs/monitoring.md, "Events") ----
// "x_high warning set", "offline", "baseline x 2 y 0 by console admin".
function eventText(e) {
  if (e.kind === "alarm") return e.alarm + " " + e.level + " " + e.state;
  if (e.kind === "baseline") return "baseline by " + (e.by || "?");
  if (e.kind === "wrong_device") return "wrong device " + e.state + ": " + (e.text || "");
  return e.kind;
}
function eventValue(e) {
  if (e.kind === "baseline" && e.value) return "x " + e.value.x + " y " + e.value.y;
  return valueText(e.value);
}
function eventRows(tbody, events, keys) {
  tbody.innerHTML = "";
  for (const e of events) {
    const row = document.createElement("tr");
    row.className = e.kind === "alarm" ? "event " + e.level + (e.state === "clear" ? " clear" : "") : "event";
    const cells = {time: e.time, local: new Date(e.unix_ms).toLocaleString(), sensor: e.sensor,
                   event: eventText(e), value: eventValue(e), threshold: valueText(e.threshold)};
    for (const key of keys) {
      const cell = document.createElement("td");
      cell.textContent = cells[key] === undefined ? "" : cells[key];
      cell.dataset.key = key;
      row.appendChild(cell);
    }
    tbody.appendChild(row);
  }
}
async function loadEvents(event) {
  if (event) event.preventDefault();
  const query = new URLSearchParams();
  for (const key of ["sensor", "kind", "from", "limit"]) {
    const v = $("events-" + key).value.trim();
    if (v !== "") query.set(key, v);
  }
  try {
    const events = await getJson("/api/events?" + query.toString());
    eventRows(document.querySelector("#events-table tbody"), events,
              ["time", "sensor", "event", "value", "threshold"]);
    say("events-message", events.length + " event(s), newest first.");
  } catch (e) {
    if (!(e instanceof LoggedOut)) say("events-message", "Could not read the events: " + e.message, "bad");
  }
}
async function refreshRecentEvents() {
  try {
    eventRows(document.querySelector("#recent-events tbody"), await getJson("/api/events?limit=10"),
              ["local", "sensor", "event", "value"]);
  } catch (e) {
    // the next poll tries again; the banner says when the gateway is unreachable
  }
}

// ---- the audit trail ----
async function loadAudit(event) {
  if (event) event.preventDefault();
  const query = new URLSearchParams();
  for (const key of ["door", "sensor", "who", "setting", "limit"]) {
    const v = $("audit-" + key).value.trim();
    if (v !== "") query.set(key, v);
  }
  try {
    const r = await api("GET", "/api/audit?" + query.toString());
    const tbody = document.querySelector("#audit-table tbody");
    tbody.innerHTML = "";
    for (const rec of r.records || []) {
      const row = document.createElement("tr");
      for (const key of ["time", "door", "who", "sensor", "setting", "old", "new", "result"]) {
        const cell = document.createElement("td");
        cell.textContent = key === "time" && !rec.time && rec.unix_ms ? new Date(rec.unix_ms).toISOString()
                         : valueText(rec[key]);
        cell.dataset.key = key;
        row.appendChild(cell);
      }
      tbody.appendChild(row);
    }
    say("audit-message", (r.records || []).length + " record(s), newest first.");
  } catch (e) {
    say("audit-message", "Could not read the audit trail: " + e.message, "bad");
  }
}

// ---- start: which page is this? ----
async function start() {
  let data = null, status = 0;
  try {
    const reply = await fetch("/api/session", {cache: "no-store", credentials: "same-origin"});
    status = reply.status;
    data = await reply.json();
  } catch (e) {
    data = null;   // an older gateway, or none: today's page, whose polls say which
  }
  if (data && data.accounts && status === 200) setSession(data);
  else if (data && data.accounts) showLogin();
  poll();
}

$("login").addEventListener("submit", logIn);
$("logout").addEventListener("click", logOut);
for (const button of document.querySelectorAll(".tab"))
  button.addEventListener("click", () => showTab(button.dataset.tab));
$("confirm-ok").addEventListener("click", () => answerConfirm(true));
$("detail-reset").addEventListener("click", () => resetCounters("sensor", settingsFor, $("counters-message")));
$("detail-baseline-set").addEventListener("click", () => changeBaseline("current"));
$("detail-baseline-clear").addEventListener("click", () => changeBaseline("clear"));
$("confirm-cancel").addEventListener("click", () => answerConfirm(false));
$("raw-form").addEventListener("submit", sendRaw);
$("config-reload").addEventListener("click", loadConfig);
$("config-check").addEventListener("click", checkConfig);
$("config-diff").addEventListener("click", showDiff);
$("config-apply").addEventListener("click", applyConfig);
$("config-confirm").addEventListener("click", confirmConfig);
$("audit-form").addEventListener("submit", loadAudit);
$("events-form").addEventListener("submit", loadEvents);

start();
