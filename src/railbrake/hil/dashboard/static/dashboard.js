// railbrake HIL dashboard: polls the loop's live snapshot and draws scrolling plots on canvases.
// Everything here ships with the package: no library, no font, nothing from the network.
"use strict";
const token = new URLSearchParams(location.search).get("token") || "";   // sent as Authorization: Bearer
const WINDOW_S = 30;           // seconds of history drawn
const POLL_MS = 100;
const history = [];            // snapshots, oldest first
let info = null, atmosphere = null, polling = true;

const $ = (id) => document.getElementById(id);
const kmh = (v) => v * 3.6;
const barg = (p) => (p - atmosphere) / 1e5;

async function getJSON(path) {
  const r = await fetch(path, {cache: "no-store", headers: {"Authorization": "Bearer " + token}});
  return r.json();
}

async function postJSON(path, body) {
  const r = await fetch(path, {method: "POST", headers: {"Content-Type": "application/json",
                                                        "Authorization": "Bearer " + token},
                               body: JSON.stringify(body)});
  return r.json();
}

function axlesOfCar() {
  const car = Number($("car").value || 1);
  return [0, 1, 2, 3].map((k) => (car - 1) * info.axles_per_car + k);
}

// Plot layout (px): a legend band on top, value labels in the left margin, time labels and the
// time axis's name in the bottom band; no two texts share a pixel. Each text's box goes into
// canvas.dataset.labels (JSON) so a test can check exactly that.
const FONT = "11px sans-serif", TOP = 26, LEFT = 70, RIGHT = 12, BOTTOM = 34, TICK_S = 10;
const COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"];

function text(ctx, boxes, s, x, y, align) {
  // y: the text's baseline; align: "left", "right" or "center" about x
  const m = ctx.measureText(s), w = m.width;
  const x0 = align === "right" ? x - w : align === "center" ? x - w / 2 : x;
  ctx.textAlign = "left"; ctx.fillText(s, x0, y);
  boxes.push({text: s, x0: x0, x1: x0 + w, y0: y - m.actualBoundingBoxAscent, y1: y + m.actualBoundingBoxDescent});
  return x0 + w;
}

function value(v) {   // at most 4 significant digits, short enough for the left margin
  const a = Math.abs(v);
  const s = a !== 0 && (a < 1e-3 || a >= 1e5) ? v.toExponential(2) : String(Number(v.toPrecision(4)));
  return s.replace(/^-/, "\u2212");   // the minus sign of the time axis
}

function plot(canvas, series, quantity) {   // quantity: the value axis's name and unit
  const ctx = canvas.getContext("2d"), w = canvas.width, h = canvas.height, boxes = [];
  ctx.clearRect(0, 0, w, h);
  if (!history.length) return;
  const now = history[history.length - 1].time;
  let lo = Infinity, hi = -Infinity;
  for (const s of series) for (const p of history) { const v = s.get(p); lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!(hi > lo)) { hi = lo + 1; }
  const x = (t) => LEFT + (w - LEFT - RIGHT) * (t - now + WINDOW_S) / WINDOW_S;
  const y = (v) => h - BOTTOM - (h - TOP - BOTTOM) * (v - lo) / (hi - lo);
  ctx.font = FONT;
  ctx.strokeStyle = "#bbb"; ctx.strokeRect(LEFT, TOP, w - LEFT - RIGHT, h - TOP - BOTTOM);
  ctx.fillStyle = "#444";
  // values: top and bottom of the range, right-aligned in the left margin; the axis's name and
  // unit on the top band, the legend after it
  text(ctx, boxes, value(hi), LEFT - 4, TOP + 4, "right");
  text(ctx, boxes, value(lo), LEFT - 4, h - BOTTOM + 4, "right");
  const named = text(ctx, boxes, quantity, 2, 14, "left");
  // time relative to now: -30 .. 0 s, then the axis's name under them
  for (let t = -WINDOW_S; t <= 0; t += TICK_S) {
    const px = x(now + t);
    ctx.beginPath(); ctx.moveTo(px, h - BOTTOM); ctx.lineTo(px, h - BOTTOM + 3); ctx.stroke();
    const align = t === -WINDOW_S ? "left" : t === 0 ? "right" : "center";   // the ends inside the plot's width
    text(ctx, boxes, t === 0 ? "0" : "\u2212" + (-t), px, h - BOTTOM + 15, align);
  }
  text(ctx, boxes, "t \u2212 now [s]", LEFT + (w - LEFT - RIGHT) / 2, h - 4, "center");
  // legend: one entry per series, a line of its colour then its name, on the top band
  let lx = Math.max(LEFT, named + 16);
  series.forEach((s, i) => {
    ctx.strokeStyle = ctx.fillStyle = COLOURS[i % COLOURS.length];
    ctx.beginPath(); ctx.moveTo(lx, 10); ctx.lineTo(lx + 14, 10); ctx.stroke();
    lx = text(ctx, boxes, s.label, lx + 18, 14, "left") + 14;
  });
  ctx.save();
  ctx.beginPath(); ctx.rect(LEFT, TOP, w - LEFT - RIGHT, h - TOP - BOTTOM); ctx.clip();
  series.forEach((s, i) => {
    ctx.strokeStyle = COLOURS[i % COLOURS.length]; ctx.beginPath();
    history.forEach((p, k) => { const px = x(p.time), py = y(s.get(p)); k ? ctx.lineTo(px, py) : ctx.moveTo(px, py); });
    ctx.stroke();
  });
  ctx.restore();
  canvas.dataset.labels = JSON.stringify(boxes);
}

function row(table, cells) {
  const tr = document.createElement("tr");
  cells.forEach((c, i) => { const td = document.createElement("td"); td.textContent = c; if (i) td.className = "num"; tr.appendChild(td); });
  table.appendChild(tr);
}

function show(s) {
  $("time").textContent = s.time.toFixed(3);
  $("speed").textContent = kmh(s.speed).toFixed(2);
  $("speed").dataset.time = s.time;
  $("speed").dataset.value = kmh(s.speed);
  $("safe").textContent = s.safe ? "SAFE STATE" : "BCU in control";
  $("safe").className = "state " + (s.safe ? "safe" : "normal");
  const numbers = $("numbers"); numbers.textContent = "";
  $("demand").textContent = s.brake_demand_text;
  row(numbers, ["brake demand", s.brake_demand_text]);
  row(numbers, ["main reservoir", barg(s.main_reservoir).toFixed(2) + " bar g"]);
  s.supply.forEach((p, c) => row(numbers, ["supply car " + (c + 1), barg(p).toFixed(2) + " bar g"]));
  for (const [k, v] of Object.entries(s.counters)) row(numbers, [k.replace("_", " "), String(v)]);
  const valves = $("valves"); valves.textContent = "";
  row(valves, ["axle", "hold", "vent", "slip"]);
  axlesOfCar().forEach((a) => row(valves, ["c" + $("car").value + "a" + (a % 4 + 1), s.hold[a] ? "HOLD" : "-",
                                           s.vent[a] ? "VENT" : "-", s.slip[a].toFixed(3)]));
  const axles = axlesOfCar(), name = (a) => "c" + $("car").value + "a" + (a % 4 + 1);
  plot($("speeds"), [{label: "train", get: (p) => kmh(p.speed)}].concat(
    axles.map((a) => ({label: name(a), get: (p) => kmh(p.wheel_speed[a])}))), "speed [km/h]");
  plot($("cylinders"), axles.map((a) => ({label: name(a), get: (p) => barg(p.cylinder[a])})), "pressure [bar g]");
  plot($("slips"), axles.map((a) => ({label: name(a), get: (p) => p.slip[a]})), "slip [1]");
}

async function poll() {
  try {
    const reply = await getJSON("/api/snapshot");
    const s = reply.snapshot;
    if (s && (!history.length || s.time > history[history.length - 1].time)) {
      history.push(s);
      while (history.length && history[0].time < s.time - WINDOW_S) history.shift();
      show(s);
    }
    $("status").textContent = reply.stopping ? "stopping" : "";
  } catch (e) {
    $("status").textContent = "the run has ended";
    polling = false;
  }
  if (polling) setTimeout(poll, POLL_MS);
}

async function changeFault(command) {
  const fault = {type: $("fault-type").value, car: Number($("fault-car").value)};
  if ($("fault-axle").value) fault.axle = Number($("fault-axle").value);
  const key = info.fault_values[fault.type];   // noise, leak_area or pressure, e.g. "1.5 bar"
  if (key && command === "inject" && $("fault-value").value) fault[key] = $("fault-value").value;
  const reply = await postJSON("/api/fault", {command: command, fault: fault});
  $("fault-answer").textContent = reply.ok ? reply.text + " at t = " + reply.time_s.toFixed(3) + " s" : reply.error;
  $("fault-answer").dataset.ok = reply.ok;
  $("fault-answer").dataset.time = reply.ok ? reply.time_s : "";
}

async function start() {
  info = await getJSON("/api/info");
  while (info.atmosphere === null) {   // the run has not started yet
    await new Promise((done) => setTimeout(done, 200));
    info = await getJSON("/api/info");
  }
  atmosphere = info.atmosphere;
  for (let c = 1; c <= info.cars; ++c) $("car").add(new Option("car " + c, String(c)));
  info.fault_kinds.forEach((k) => $("fault-type").add(new Option(k, k)));
  $("fault-type").onchange = () => {
    const key = info.fault_values[$("fault-type").value];
    $("fault-value-key").textContent = key || "value";
    $("fault-value").disabled = !key;
  };
  $("fault-type").onchange();
  $("fault-car").max = info.cars;
  $("inject").onclick = () => changeFault("inject");
  $("clear").onclick = () => changeFault("clear");
  $("stop").onclick = () => postJSON("/api/stop", {});
  $("car").onchange = () => history.length && show(history[history.length - 1]);
  poll();
}
start();
