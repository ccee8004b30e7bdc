// The console's traffic view (docs/web-console.md, "Traffic"), served as /traffic_view.js after
// /status_page.js, whose helpers it uses (api, may, clock, currentTab). On each
// bus of the Buses tab, for an admin only (frames carry settings): a live list of the frames its
// line carries, from GET /api/buses/NAME/frames, polled while the view is open, not paused and
// the tab shown; filtered by address; and the bus's black box as a pcapng file to download.
"use strict";
const TRAFFIC_POLL_MS = 500;
const TRAFFIC_ROWS = 500;       // the newest kept in the list; older rows go
const TRAFFIC_FULL = 300;       // a reply this long may have left frames for the next: ask at once

// bus name -> {root, bus, next, paused, busy, timer, watch}; `watch` counts the openings, so a
// reply that comes after the view was closed and opened again is dropped.
const trafficViews = new Map();

// The view's markup in a bus's panel (renderScans): closed, so nothing is polled until opened.
function addTrafficView(panel, bus) {
  const root = document.createElement("details");
  root.className = "traffic";
  root.dataset.needs = "admin";
  root.dataset.hide = "";          // applyRole hides it from other roles, rather than disabling it
  root.innerHTML =
    "<summary>Traffic</summary>" +
    '<div class="row">' +
    // Text, not numeric: several addresses are separated by commas or spaces.
    '<label class="field">Address <input class="traffic-filter" autocapitalize="none" ' +
    'spellcheck="false" placeholder="all" size="8"></label>' +
    '<button class="button traffic-pause" type="button">Pause</button>' +
    '<a class="button traffic-download" download>Download the last minute</a></div>' +
    '<div class="message traffic-message" role="status"></div>' +
    '<div class="scroll"><table class="list traffic-list"><thead><tr><th>Time</th><th>Dir</th>' +
    "<th>Address</th><th>Function</th><th>Verdict</th><th>Bytes</th></tr></thead>" +
    "<tbody></tbody></table></div>";
  root.querySelector(".traffic-download").href =
    "/api/buses/" + encodeURIComponent(bus) + "/capture.pcapng";
  const view = {root, bus, next: null, paused: false, busy: false, timer: null, watch: 0};
  trafficViews.set(bus, view);
  root.addEventListener("toggle", () => {
    if (root.open) pollTraffic(view);
    else resetTraffic(view);
  });
  const filter = root.querySelector(".traffic-filter");
  filter.addEventListener("input", () => filterTraffic(view));
  // The view sits in the scan's form: Enter in the filter must not start a scan.
  filter.addEventListener("keydown", (e) => { if (e.key === "Enter") e.preventDefault(); });
  root.querySelector(".traffic-pause").addEventListener("click", () => pauseTraffic(view));
  // On a phone the bytes column is hidden: a tap on a row shows its bytes.
  root.querySelector("tbody").addEventListener("click", (e) => {
    e.target.closest("tr")?.classList.toggle("open");
  });
  panel.appendChild(root);
}

function trafficWatched(view) {
  return view.root.open && !view.paused && !view.root.hidden && currentTab === "buses" &&
         may("admin");
}

async function pollTraffic(view) {
  clearTimeout(view.timer);
  view.timer = null;
  if (!view.root.open || view.busy) return;
  let again = TRAFFIC_POLL_MS;
  if (trafficWatched(view)) {
    view.busy = true;
    const asked = "/api/buses/" + encodeURIComponent(view.bus) + "/frames" +
                  (view.next === null ? "" : "?after=" + view.next);
    const watch = view.watch;
    try {
      const r = await api("GET", asked);
      if (view.root.open && !view.paused && view.watch === watch) {
        addTrafficRows(view, r);
        view.next = r.next;
        if (r.frames.length >= TRAFFIC_FULL) again = 0;
      }
    } catch (e) {
      trafficSay(view, "Could not read the traffic: " + e.message, "bad");
      // Logged out, not allowed or no such bus: asking again would not change that.
      again = [401, 403, 404].includes(e.status) ? null : TRAFFIC_POLL_MS * 4;
    } finally {
      view.busy = false;
    }
  }
  if (view.root.open && again !== null) view.timer = setTimeout(() => pollTraffic(view), again);
}

// "14:03:07.125", the frame's time on this browser's clock.
function trafficTime(micros) {
  const date = new Date(micros / 1000);
  return clock(date) + "." + String(date.getMilliseconds()).padStart(3, "0");
}

// A frame stands out red unless the line took it whole: a request, or a reply whose framing and
// checksum held, in the words the line and the framers give it ("CRC ok", "LRC ok", "MBAP
// transaction 7 unit 1", "CR LF, no checksum", "reply"), that is no refusal ("nak 0x03") and
// decoded without a "but". Any other verdict (skipped, no reply, late, a collision, one this
// page does not know) is red.
const TRAFFIC_TAKEN = /^(request$|reply|CRC ok|LRC ok|MBAP transaction|CR LF)/;
function trafficBad(f) {
  return !TRAFFIC_TAKEN.test(f.verdict) || f.verdict.includes(", but ") || !!f.refusal;
}

function addTrafficRows(view, r) {
  const tbody = view.root.querySelector("tbody");
  const filter = trafficFilter(view);
  const rows = document.createDocumentFragment();
  if (r.missed > 0) {
    const gap = document.createElement("tr");
    gap.className = "gap";
    gap.innerHTML = '<td colspan="6"></td>';
    gap.firstChild.textContent = r.missed + " frame(s) left the black box before they were shown";
    rows.prepend(gap);
  }
  for (const f of r.frames) {
    const row = document.createElement("tr");
    row.dataset.n = f.n;
    row.dataset.address = f.address === null ? "" : String(f.address);
    row.innerHTML = '<td class="time num"></td><td class="dir"></td><td class="address num"></td>' +
                    '<td class="function"></td><td class="verdict"></td><td class="bytes hex"></td>';
    const cells = row.children;
    cells[0].textContent = trafficTime(f.time_us);
    cells[1].textContent = f.direction === "out" ? "\u2192" : "\u2190";
    cells[1].title = f.direction === "out" ? "to the devices" : "from the devices";
    cells[2].textContent = f.address === null ? "\u2013" : f.address;
    cells[3].textContent = f.function === null ? "\u2013" : f.function;
    if (f.values) {  // what a reply says, decoded by the bus's protocol
      const values = document.createElement("span");
      values.className = "values";
      values.textContent = f.values;
      cells[3].append(document.createElement("br"), values);
    }
    cells[4].textContent = f.verdict + (f.refusal ? " \u00B7 " + f.refusal : "");
    if (trafficBad(f)) cells[4].classList.add("bad");
    cells[5].textContent = f.bytes;
    row.hidden = !trafficShown(row, filter);
    rows.prepend(row);   // newest at the top
  }
  tbody.prepend(rows);
  while (tbody.rows.length > TRAFFIC_ROWS) tbody.lastElementChild.remove();
  const shown = tbody.querySelectorAll("tr[data-n]:not([hidden])").length;
  trafficSay(view, (view.paused ? "Paused. " : "") + shown + " frame(s) shown, the newest first; " +
             "the black box keeps " + r.keep_s + " s.");
  const download = view.root.querySelector(".traffic-download");
  download.textContent = r.keep_s === 60 ? "Download the last minute"
                                         : "Download the last " + r.keep_s + " s";
}

// The addresses asked for ("5", "5, 7"); empty: all.
function trafficFilter(view) {
  return view.root.querySelector(".traffic-filter").value.split(/[\s,;]+/).filter((a) => a !== "");
}
function trafficShown(row, filter) {
  return filter.length === 0 || filter.includes(row.dataset.address);
}
function filterTraffic(view) {
  const filter = trafficFilter(view);
  for (const row of view.root.querySelectorAll("tbody tr[data-n]"))
    row.hidden = !trafficShown(row, filter);
  // A gap says nothing of one address: shown only when all are.
  for (const row of view.root.querySelectorAll("tbody tr.gap")) row.hidden = filter.length > 0;
}

function pauseTraffic(view) {
  view.paused = !view.paused;
  view.root.dataset.paused = String(view.paused);
  view.root.querySelector(".traffic-pause").textContent = view.paused ? "Resume" : "Pause";
  // Resumed, it goes on from the last frame shown: the black box kept what came meanwhile.
  if (!view.paused) pollTraffic(view);
  else trafficSay(view, "Paused: no new frames until Resume.");
}

function trafficSay(view, text, kind) {
  const el = view.root.querySelector(".traffic-message");
  el.textContent = text;
  el.className = "message traffic-message" + (kind ? " " + kind : "");
}

// A closed view starts over when opened again (a new watch, as the audit trail has it).
function resetTraffic(view) {
  view.watch += 1;
  clearTimeout(view.timer);
  view.timer = null;
  view.next = null;
  view.paused = false;
  delete view.root.dataset.paused;
  view.root.querySelector(".traffic-pause").textContent = "Pause";
  view.root.querySelector("tbody").innerHTML = "";
  trafficSay(view, "");
}

// Logged out: nothing a previous user saw stays on the page.
function clearTraffic() {
  for (const view of trafficViews.values()) {
    view.root.open = false;
    resetTraffic(view);
  }
}
