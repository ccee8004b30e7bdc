// Decodes Sparkplug B payloads with Eclipse Tahu's reference JavaScript library
// (sparkplug-payload, installed by package.json and package-lock.json beside this file) for the
// Sparkplug e2e tests (tests/e2e/sparkplug/spb_e2e/tahu.py): one payload a line on stdin, in
// base64; one line of JSON a payload on stdout, what decodePayload() gives a host. A 64-bit
// number (protobufjs's Long) becomes {"long": "<decimal>"} so no digit is lost; a payload Tahu
// cannot decode becomes {"error": "<why>"}.
//
// Usage: NODE_PATH=<install dir>/node_modules node decode.js < payloads.b64
"use strict";

const readline = require("readline");
const Long = require("long");
const sparkplug = require("sparkplug-payload").get("spBv1.0");

function plain(value) {
  if (Long.isLong(value)) return { long: value.toString() };
  if (value instanceof Uint8Array) return { bytes: Buffer.from(value).toString("base64") };
  if (Array.isArray(value)) return value.map(plain);
  if (value !== null && typeof value === "object") {
    const out = {};
    for (const key of Object.keys(value)) out[key] = plain(value[key]);
    return out;
  }
  return value === undefined ? null : value;
}

const lines = readline.createInterface({ input: process.stdin });
lines.on("line", (line) => {
  let out;
  try {
    out = plain(sparkplug.decodePayload(Buffer.from(line.trim(), "base64")));
  } catch (e) {
    out = { error: String(e) };
  }
  process.stdout.write(JSON.stringify(out) + "\n");
});
