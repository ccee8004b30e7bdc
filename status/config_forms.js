// The console's guided configuration (docs/web-console.md, "Guided configuration"), served as
// /config_forms.js after /status_page.js, whose helpers it uses ($, esc, api, say, askConfirm,
// showTab, loadConfig, showDiff). Forms add, change and remove a [[bus]] or a [[sensor]] of the
// editor's text: the gateway describes each key as docs/configuration.md does
// (GET /api/config/form), reads the text's tables (POST /api/config/tables) and makes the
// changed text, checked as `tiltgate check` checks it (POST /api/config/form). A form's text goes
// into the editor; the editor's Apply, with its diff and confirmation, applies it.
"use strict";

let formKeys = null;       // GET /api/config/form: {bus: [...], sensor: [...]}
let formTables = null;     // POST /api/config/tables of the editor's text
let openForm = null;       // {table, action, name}

// A reference cell as text a person reads: `code` kept as code, links as their words.
function referenceHtml(markdown) {
  return esc(markdown.replace(/\[([^\]]+)\]\([^)]*\)/g, "$1"))
    .replace(/`([^`]+)`/g, "<code>$1</code>");
}
function fieldId(key) { return "field-" + key.replace(/\./g, "-"); }
function plainDefault(key) {
  if (key.required || key.default === "none" || key.default === "required") return "";
  return key.default.replace(/`/g, "").replace(/^"(.*)"$/, "$1");
}

async function refreshTables() {
  if (!session.user || session.role !== "admin") return;
  try {
    if (formKeys === null) formKeys = await api("GET", "/api/config/form");
    formTables = await api("POST", "/api/config/tables", {text: $("editor").value});
  } catch (e) {
    say("forms-message", "Could not read the buses and sensors: " + e.message, "bad");
    return;
  }
  const body = $("forms-tables").querySelector("tbody");
  body.innerHTML = "";
  // Its own message stays until the text reads again; a form's message stays as it is.
  const message = $("forms-message");
  if (formTables.error) {
    say("forms-message", "The text is " + formTables.error + ": correct it in the editor to use the forms.", "bad");
    message.dataset.unreadable = "true";
    return;
  }
  if (message.dataset.unreadable) { say("forms-message", ""); delete message.dataset.unreadable; }
  const rows = formTables.buses.map((t) => ["bus", t, [t.values.port, t.values.protocol || "rieker"]])
    .concat(formTables.sensors.map((t) => ["sensor", t, ["bus " + (t.values.bus || "?"), t.values.model,
      "address " + (t.values.address || "?"), "unit " + (t.values.unit_id || "?")]]));
  for (const [table, t, facts] of rows) {
    const row = document.createElement("tr");
    row.dataset.table = table;
    row.dataset.name = t.name;
    row.innerHTML = "<td>" + table + "</td><td>" + esc(t.name) + "</td><td>" +
      esc(facts.filter(Boolean).join(" \u00B7 ")) + "</td><td class=\"actions\"></td>";
    for (const [label, action] of [["Edit", "edit"], ["Remove", "remove"]]) {
      const button = document.createElement("button");
      button.type = "button";
      button.className = "button small " + action;
      button.textContent = label;
      button.setAttribute("aria-label", label + " " + table + " " + t.name);
      button.addEventListener("click", () => action === "edit" ? showForm(table, "edit", t)
                                                               : removeTable(table, t.name));
      row.lastChild.appendChild(button);
    }
    body.appendChild(row);
  }
}

// One key's input: a list where the reference names the values (or the buses, for a sensor's
// bus), true/false for a boolean, text otherwise; the reference's meaning under it.
function fieldHtml(key, value, fixed, buses) {
  const id = fieldId(key.key);
  const name = key.key.includes(".") ? key.key.split(".")[1] : key.key;
  let input;
  const options = key.key === "bus" && buses ? buses : key.choices.length ? key.choices
                : key.type === "boolean" ? ["true", "false"] : null;
  if (fixed) {
    input = '<input id="' + id + '" value="(written in the text)" disabled>';
  } else if (options) {
    const none = key.required ? "choose\u2026" : "default" + (plainDefault(key) ? ": " + plainDefault(key) : "");
    input = '<select id="' + id + '" data-key="' + esc(key.key) + '"><option value="">' + esc(none) + "</option>" +
      options.map((o) => "<option" + (o === value ? " selected" : "") + ">" + esc(o) + "</option>").join("") +
      (value && !options.includes(value) ? "<option selected>" + esc(value) + "</option>" : "") + "</select>";
  } else {
    const numeric = key.type === "integer" || key.type.startsWith("number");
    input = '<input id="' + id + '" data-key="' + esc(key.key) + '" value="' + esc(value || "") + '"' +
      (numeric ? ' inputmode="decimal"' : "") + ' placeholder="' + esc(plainDefault(key)) + '" autocomplete="off">';
  }
  return '<div class="field" data-field="' + esc(key.key) + '"><label for="' + id + '">' + esc(name) +
    (key.required ? ' <span class="required">required</span>' : "") + "</label>" + input +
    '<div class="field-error" role="alert"></div><div class="help">' + referenceHtml(key.meaning) +
    (key.allowed ? '<span class="allowed"> Allowed: ' + referenceHtml(key.allowed) + "</span>" : "") +
    (fixed ? " <em>Written as a table: change it in the text.</em>" : "") + "</div></div>";
}

// The form for `table` ("bus", "sensor"): `action` "add" (with `start` values, a scan's
// proposal say) or "edit" of table `current` from formTables.
async function showForm(table, action, current, start) {
  if (formTables === null || formKeys === null) await refreshTables();
  if (formKeys === null) return;
  openForm = {table, action, name: current ? current.name : null};
  const values = Object.assign({}, current ? current.values : {}, start || {});
  if (action === "add" && table === "sensor" && !values.unit_id && formTables && formTables.free_unit_id)
    values.unit_id = String(formTables.free_unit_id);
  const fixed = current ? current.fixed : [];
  const buses = formTables && !formTables.error ? formTables.buses.map((b) => b.name) : null;
  let main = "", more = "", moreSet = 0, group = "";
  for (const key of formKeys[table]) {
    if (key.type === "table") continue;  // a group: its keys follow, under its name
    let html = "";
    const groupName = key.key.includes(".") ? key.key.split(".")[0] : "";
    if (groupName !== group) {
      const row = formKeys[table].find((k) => k.key === groupName);
      html += groupName ? '<h4 class="group">' + esc(groupName) + (row ? ' <span class="help">' +
        referenceHtml(row.meaning) + "</span>" : "") + "</h4>" : "";
      group = groupName;
    }
    html += fieldHtml(key, values[key.key], fixed.includes(key.key), buses);
    if (key.required) main += html;
    else { more += html; if (values[key.key] || fixed.includes(key.key)) moreSet++; }
  }
  $("table-form-title").textContent = action === "add" ? "Add a " + table
                                                       : "Change " + table + " " + current.name;
  $("table-form-fields").innerHTML = main;
  $("table-form-more-fields").innerHTML = more;
  $("table-form-more-count").textContent = moreSet ? " (" + moreSet + " set)" : "";
  $("table-form-more").open = moreSet > 0;
  $("table-form-errors").innerHTML = "";
  $("table-form").hidden = false;
  showTab("config");
  $("table-form").scrollIntoView({block: "start"});
  const first = $("table-form").querySelector("input:not([disabled]), select");
  if (first) first.focus();
}

function hideForm() {
  $("table-form").hidden = true;
  openForm = null;
}

// The gateway's answer to a form: errors at their fields, the others above the form.
function showFormErrors(errors) {
  for (const el of $("table-form").querySelectorAll(".field-error")) el.textContent = "";
  for (const el of $("table-form").querySelectorAll(".field")) el.classList.remove("bad");
  const list = $("table-form-errors");
  list.innerHTML = "";
  let firstField = null;
  for (const err of errors) {
    if (err.before) {
      const item = document.createElement("li");
      item.className = "before";
      item.textContent = "Already in the text before this form: " + (err.line ? "line " + err.line + ": " : "") + err.message;
      list.appendChild(item);
      continue;
    }
    const field = err.field && $("table-form").querySelector('.field[data-field="' + CSS.escape(err.field) + '"]');
    if (field) {
      field.classList.add("bad");
      field.querySelector(".field-error").textContent = err.message;
      if (field.closest("details")) field.closest("details").open = true;
      firstField = firstField || field;
    } else {
      const item = document.createElement("li");
      item.textContent = err.line ? "line " + err.line + ": " + (err.key ? err.key + ": " : "") + err.message : err.text;
      list.appendChild(item);
    }
  }
  if (firstField) firstField.querySelector("input, select").focus();
}

// What the gateway made of a form: into the editor when valid, with the changes shown.
function takeFormText(reply, done) {
  showFormErrors(reply.errors || []);
  if (!reply.ok) {
    say("forms-message", (reply.errors || []).filter((e) => !e.before).length + " problem(s): see the form.", "bad");
    return false;
  }
  $("editor").value = reply.text;
  const d = showDiff();
  say("forms-message", done + ": now in the editor (+" + (d ? d.added : 0) + " \u2212" +
      (d ? d.removed : 0) + " lines, shown below). Apply it with the editor's Apply.", "ok");
  refreshTables();
  return true;
}

async function submitForm(event) {
  event.preventDefault();
  if (!openForm) return;
  const values = {};
  for (const input of $("table-form").querySelectorAll("[data-key]"))
    if (!input.disabled && (openForm.action === "edit" || input.value.trim() !== "")) values[input.dataset.key] = input.value;
  try {
    const reply = await api("POST", "/api/config/form", {text: $("editor").value, action: openForm.action,
                                                        table: openForm.table, name: openForm.name || "", values});
    const done = openForm.action === "add" ? "The " + openForm.table + " " + (values.name || "") + " is added"
                                           : "The " + openForm.table + " " + openForm.name + " is changed";
    if (takeFormText(reply, done)) hideForm();
  } catch (e) {
    showFormErrors([{field: null, text: e.message}]);
  }
}

async function removeTable(table, name) {
  if (!await askConfirm("Remove " + table + " " + name + " from the configuration text? Nothing changes " +
                        "on the gateway until you apply the text.")) return;
  try {
    const reply = await api("POST", "/api/config/form", {text: $("editor").value, action: "remove", table, name});
    if (!reply.ok) {
      const why = (reply.errors || []).filter((e) => !e.before).map((e) => e.message).join("; ");
      say("forms-message", "Not removed: the text without it would not be valid (" + why + ").", "bad");
      return;
    }
    takeFormText(reply, "The " + table + " " + name + " is removed");
  } catch (e) {
    say("forms-message", e.message, "bad");
  }
}

// A scan's proposal ([[sensor]] text) as the Add a sensor form, filled.
async function addScannedSensor(text) {
  if (servedConfig === null) await loadConfig();
  try {
    const read = await api("POST", "/api/config/tables", {text});
    const proposal = read.sensors && read.sensors[0] ? read.sensors[0].values : {};
    await showForm("sensor", "add", null, proposal);
    say("forms-message", "The scan's proposal is in the form: check it, then put it in the editor.", "ok");
  } catch (e) {
    say("forms-message", e.message, "bad");
  }
}

$("form-add-bus").addEventListener("click", () => showForm("bus", "add"));
$("form-add-sensor").addEventListener("click", () => showForm("sensor", "add"));
$("table-form").addEventListener("submit", submitForm);
$("table-form-cancel").addEventListener("click", hideForm);
$("editor").addEventListener("change", refreshTables);
