// railbrake HIL dashboard: polls the loop's live snapshot and draws scrolling plots on canvases.
// Everything here ships with the package: no library, no font, nothing from the network.
"use strict";
const token = new URLSearchParams(location.search).get("token") || "";
const WINDOW_S = 30;           // seconds of history drawn
const POLL_MS = 100;
const history = [];            // snapshots, oldest first
let info = null, atmosphere = null, polling = true;

const $ = (id) => document.getElementById(id);
const kmh = (v) => v * 3.6;
const barg = (p) => (p - atmosphere) / 1e5;

async function getJSON(path) {
  const r = await fetch(path + (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token),
                        {cache: "no-store"});
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

function plot(canvas, series, unit) {
  const ctx = canvas.getContext("2d"), w = canvas.width, h = canvas.height;
  ctx.clearRect(0, 0, w, h);
  if (!history.length) return;
  const t1 = history[history.length - 1].time, t0 = t1 - WINDOW_S;
  let lo = Infinity, hi = -Infinity;
  for (const s of series) for (const p of history) { const v = s.get(p); lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!(hi > lo)) { hi = lo + 1; }
  const x = (t) => 40 + (w - 50) * (t - t0) / WINDOW_S, y = (v) => h - 15 - (h - 25) * (v - lo) / (hi - lo);
  ctx.font = "11px sans-serif"; ctx.fillStyle = "#444";
  ctx.fillText(hi.toPrecision(4) + " " + unit, 2, 12); ctx.fillText(lo.toPrecision(4), 2, h - 3);
  ctx.fillText((t0 > 0 ? t0 : 0).toFixed(1) + " s", 40, h - 3); ctx.fillText(t1.toFixed(1) + " s", w - 60, h - 3);
  const colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"];
  series.forEach((s, i) => {
    ctx.strokeStyle = colours[i % colours.length]; ctx.beginPath();
    history.forEach((p, k) => { const px = x(p.time), py = y(s.get(p)); k ? ctx.lineTo(px, py) : ctx.moveTo(px, py); });
    ctx.stroke(); ctx.fillStyle = ctx.strokeStyle; ctx.fillText(s.label, 50 + 110 * i, 12);
  });
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
  row(numbers, ["brake demand", String(s.brake_demand)]);
  row(numbers, ["main reservoir", barg(s.main_reservoir).toFixed(2) + " bar g"]);
  s.supply.forEach((p, c) => row(numbers, ["supply car " + (c + 1), barg(p).toFixed(2) + " bar g"]));
  for (const [k, v] of Object.entries(s.counters)) row(numbers, [k.replace("_", " "), String(v)]);
  const valves = $("valves"); valves.textContent = "";
  row(valves, ["axle", "hold", "vent", "slip"]);
  axlesOfCar().forEach((a) => row(valves, ["c" + $("car").value + "a" + (a % 4 + 1), s.hold[a] ? "HOLD" : "-",
                                           s.vent[a] ? "VENT" : "-", s.slip[a].toFixed(3)]));
  const axles = axlesOfCar(), name = (a) => "c" + $("car").value + "a" + (a % 4 + 1);
  plot($("speeds"), [{label: "train", get: (p) => kmh(p.speed)}].concat(
    axles.map((a) => ({label: name(a), get: (p) => kmh(p.wheel_speed[a])}))), "km/h");
  plot($("cylinders"), axles.map((a) => ({label: name(a), get: (p) => barg(p.cylinder[a])})), "bar g");
  plot($("slips"), axles.map((a) => ({label: name(a), get: (p) => p.slip[a]})), "");
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
  $("fault-car").max = info.cars;
  $("inject").onclick = () => changeFault("inject");
  $("clear").onclick = () => changeFault("clear");
  $("stop").onclick = () => postJSON("/api/stop", {});
  $("car").onchange = () => history.length && show(history[history.length - 1]);
  poll();
}
start();
