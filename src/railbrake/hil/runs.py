"""The HIL loops: the plant paced at 1 kHz against an external BCU over UDP (run), and the
reference BCU server (serve_bcu), set up here and run in C (core/src/hil_runner.c, hil_bcu.c; guide
docs/hil.md, frames docs/hil-interface.md).

Python only sets up parameters and calls the C loops in chunks (0.5 s of steps for the plant, 0.5 s
of wall time for the BCU) so a caller can show progress and stop with Ctrl-C; nothing in Python
runs inside the 1 ms loop.
"""

from __future__ import annotations

import ctypes
import gc
import math
import os
import secrets
import signal
import socket
import sys
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Callable
from urllib.parse import urlsplit

import numpy as np

from railbrake import _core
from railbrake._args import instance, show, text as text_arg, whole
from railbrake.errors import InputError
from railbrake.hil.faults import FaultSwitch
from railbrake.hil.keys import key_bytes
from railbrake.hil.live import LiveView
from railbrake.resolve import resolve
from railbrake.scenario import Scenario
from railbrake.simulation.parameters import (_scenario_struct, bcu_params, kpi_dict, outside_validity_kpi, plant_params,
                                             wsp_params)
from railbrake.vehicle import load_train

DT = 1e-3                  # s, fixed by the interface
CHUNK_STEPS = 500          # plant steps per C call
CHUNK_TIME = 0.5           # s of wall time per C call at most (paced): a recording keeps up with the clock
BCU_CHUNK = 0.5            # s of wall time per C call of the BCU server
DEFAULT_HOLD_TIME = 0.1    # s
DEFAULT_LATE_TIME = 0.02   # s
DEFAULT_PRIORITY = 80      # SCHED_FIFO priority asked for by the plant (0: ask nothing)
DEFAULT_BCU_PRIORITY = 70  # the reference BCU's: below the plant's, whose deadline comes first on a shared core
# s: the longest the loop's thread waits for the GIL between two chunks while other Python threads
# (a dashboard, a control socket) run: Python's default of 5 ms would be 5 periods
GIL_SWITCH_INTERVAL = 1e-4


# ------------------------------------------------------------------ addresses

def parse_udp_url(text: str, option: str, allow_any_port: bool = False) -> tuple[str, int]:
    """'udp://HOST:PORT' -> (numeric IPv4 address, port). Port 1..65535 (0 too, for "any free
    port", when allow_any_port). Errors name the option and what is wrong."""
    option = text_arg("option", option)
    if not isinstance(text, str):
        raise TypeError(f"{option} (text) = {show(text)}: must be a string udp://HOST:PORT")
    parts = urlsplit(text)
    host, _, port_text = parts.netloc.rpartition(":")
    if parts.scheme != "udp" or not host or parts.path not in ("", "/") or parts.query or parts.fragment:
        raise InputError(f"{option} = {text!r}: expected udp://HOST:PORT")
    lowest = 0 if allow_any_port else 1
    if not port_text.isdigit() or not lowest <= int(port_text) <= 65535:
        raise InputError(f"{option} = {text!r}: port = {port_text or None!r}: must lie in [{lowest}, 65535]")
    port = int(port_text)
    try:
        address = socket.gethostbyname(host)
    except (OSError, UnicodeError):
        raise InputError(f"{option} = {text!r}: host = {host!r}: not an IPv4 address or a "
                         "name that resolves to one") from None
    return address, port


# ------------------------------------------------------------------ session and configuration

def config_digest(scenario: Scenario, n_cars: int) -> int:
    """The configuration digest plant and BCU compare (rb_hil_config_digest: train, cars, axles, step)."""
    instance("scenario", scenario, Scenario)
    n_cars = whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
    train = load_train(scenario.spec.train.preset).name
    return int(_core.rb_hil_config_digest(train.encode(), n_cars, n_cars * _core.AXLES_PER_CAR, DT))


def describe_config(scenario: Scenario, n_cars: int) -> str:
    instance("scenario", scenario, Scenario)
    n_cars = whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
    train = load_train(scenario.spec.train.preset).name
    return (f"0x{config_digest(scenario, n_cars):08x} (train {train}, {n_cars} cars, "
            f"{n_cars * _core.AXLES_PER_CAR} axles, step 1 ms)")


@contextmanager
def _sigterm_as_interrupt():
    """SIGTERM ends a run like Ctrl-C (KeyboardInterrupt between two C chunks), so the caller keeps
    what was recorded and the counters; restored afterwards. Only the main thread can install it, and
    only over the default handling (a caller's own handler, as `railbrake hil`'s, stays)."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL):
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt(f"signal {signum}")

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


# ------------------------------------------------------------------ real-time request

@dataclass
class RealTime:
    requested: bool
    memory_locked: bool = False
    fifo_priority: bool = False
    priority: int = 0

    def notes(self) -> list[str]:
        """What was refused, in plain words (empty when everything was granted)."""
        if not self.requested:
            return ["real-time scheduling not requested (--priority 0): normal time-sharing priority"]
        notes = []
        if not self.fifo_priority:
            notes.append(f"SCHED_FIFO priority {self.priority} refused (needs root or CAP_SYS_NICE, or an "
                         "rtprio limit in /etc/security/limits.conf): wake-up latency depends on the load")
        if not self.memory_locked:
            notes.append("mlockall refused (needs CAP_IPC_LOCK or a memlock limit): page faults may delay steps")
        return notes


def request_real_time(priority: int) -> RealTime:
    """Ask for locked memory and SCHED_FIFO for the calling thread (what the OS grants is reported)."""
    if priority <= 0:
        return RealTime(False)
    if priority > 99:
        raise InputError(f"priority = {priority}: must lie in [0, 99]")
    granted = _core.rb_rt_request(priority)
    return RealTime(True, bool(granted & _core.RT_MEMORY_LOCKED), bool(granted & _core.RT_FIFO_PRIORITY), priority)


class _normal_scheduling_after:
    """Restores the thread's scheduling policy on exit (a library call must not leave the caller at
    real-time priority)."""

    def __enter__(self):
        self.policy = os.sched_getscheduler(0)
        self.param = os.sched_getparam(0)
        return self

    def __exit__(self, *exc):
        try:
            os.sched_setscheduler(0, self.policy, self.param)
        except OSError:
            pass
        return False


class _own_cpu:
    """Gives the calling thread CPU `cpu` to itself within this process: the thread is pinned to it and
    every other thread of the process (the dashboard's and control socket's servers, whose own threads
    inherit the mask) is kept off it, as a HIL bench isolates the loop's core. Without it, a server
    thread runs on the loop's core while the loop sleeps between steps and leaves its caches cold for
    the next step. Masks are restored on exit. None: nothing changes."""

    def __init__(self, cpu: int | None):
        self.cpu, self.saved = cpu, {}

    def __enter__(self):
        if self.cpu is None:
            return self
        allowed = os.sched_getaffinity(0)
        if self.cpu not in allowed or len(allowed) < 2:
            raise InputError(f"cpu = {self.cpu}: must be one of this process's CPUs {sorted(allowed)} and leave "
                             "another to the rest of the process")
        me = threading.get_native_id()
        for tid in [int(t) for t in os.listdir("/proc/self/task")]:
            try:
                self.saved[tid] = os.sched_getaffinity(tid)
                os.sched_setaffinity(tid, {self.cpu} if tid == me else self.saved[tid] - {self.cpu} or allowed)
            except OSError:       # a thread that ended meanwhile
                self.saved.pop(tid, None)
        return self

    def __exit__(self, *exc):
        for tid, mask in self.saved.items():
            try:
                os.sched_setaffinity(tid, mask)
            except OSError:
                pass
        return False


# ------------------------------------------------------------------ the plant runner

@dataclass
class HilResult:
    scenario: str
    cars: int
    time: np.ndarray
    outputs: dict                 # channel name -> array (SI)
    units: dict                   # channel name -> SI unit
    counters: dict                # steps, frames_sent, received, lost, late, malformed, safe_state_steps, ...
    timing: dict                  # wake-up latency and step execution time (us), overruns
    kpis: dict                    # the KPIs of a MIL run (run_kpis)
    real_time: RealTime
    events: list = field(default_factory=list)   # (time s, kind, text), the latest logged
    atmosphere: float = math.nan  # Pa, the plant's (the train file's)
    interrupted: bool = False     # ended by Ctrl-C or SIGTERM: what was recorded until then
    mismatch: str | None = None   # why the BCU refused this plant (another configuration), else None
    loss: dict = field(default_factory=dict)   # the BCU's loss: loss_dict (lost False: never lost)
    fault_changes: list = field(default_factory=list)   # faults.FaultChange's applied while the plant ran

    def loss_report(self) -> str | None:
        """When the BCU was lost and what it cost, in one sentence (None if it never was)."""
        s = self.loss
        if not s.get("lost"):
            return None
        before = (f"its last valid frame at t = {s['last_valid_s']:.3f} s" if s["last_valid_s"] is not None
                  else "no valid frame from it before")
        again = f", lost {s['losses']} times in all" if s["losses"] > 1 else ""
        return (f"BCU lost at t = {s['at_s']:.3f} s ({before}){again}: the safe state (the BCU's emergency "
                f"demand, WSP off) applied for {s['safe_s']:.3f} s, {s['distance_m']:.1f} m run, "
                f"{s['lock_events']} wheel lock(s) began, {s['lock_axle_s']:.3f} axle-s locked")

    def timing_report(self) -> list[str]:
        t, c = self.timing, self.counters
        lines = [f"wake-up latency: p50 {t['wakeup_p50_us']:.0f} us, p99 {t['wakeup_p99_us']:.0f} us, "
                 f"max {t['wakeup_max_us']:.0f} us",
                 f"step execution: mean {t['work_mean_us']:.1f} us, p99 {t['work_p99_us']:.0f} us, "
                 f"max {t['work_max_us']:.0f} us",
                 f"overruns: {c['overruns']} of {c['steps']} steps"]
        return lines + [f"note: {n}" for n in self.real_time.notes()]


def channels(n_cars: int) -> list[tuple[str, str]]:
    n_cars = whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
    return _core.channel_list(_core.rb_hil_channel_count, _core.rb_hil_channel_info, n_cars)


def hil_config(scenario: Scenario, bcu: _core.BcuParams, duration: float | None, hold_time: float,
               late_time: float, record_interval: float | None, paced: bool, key: bytes) -> _core.HilConfig:
    spec = scenario.spec
    c = _core.HilConfig()
    c.hold_time, c.late_time = hold_time, late_time
    c.duration = spec.stop.max_time if duration is None else duration
    c.stop_speed = spec.stop.speed
    c.record_interval = spec.outputs.record_interval if record_interval is None else record_interval
    if abs(c.record_interval / DT - round(c.record_interval / DT)) > 1e-9:
        raise InputError(f"record_interval = {c.record_interval} s: must be a multiple of 1 ms")
    c.paced = int(paced)
    c.chunk_time = CHUNK_TIME if paced else 0.0
    c.adhesion_interval = _scenario_struct(scenario).adhesion_interval   # as in the MIL run
    c.session = secrets.randbits(32) or 1   # a new session per run: a BCU tells runs apart
    c.secret[:] = key
    _core.call(_core.rb_hil_safe_bcu, ctypes.byref(bcu), ctypes.byref(c.safe))
    return c


def loss_dict(result: _core.HilResult) -> dict:
    """The BCU's loss from the C result: when (s), for how long, and what it cost."""
    lost = result.losses > 0
    return {"lost": lost, "losses": int(result.losses),
            "at_s": result.lost_step * DT if lost else None,
            "last_valid_s": result.last_valid_step * DT if lost and result.last_valid_step else None,
            "safe_s": result.lost_steps * DT, "distance_m": result.lost_distance,
            "lock_events": int(result.lost_lock_events), "lock_axle_s": result.lost_lock_time}


def _drain_events(state, seen: int, total: int, on_event) -> list:
    """Events seen..total still in the C log (the latest RB_HIL_LOG_SIZE); the counters hold the rest."""
    events = []
    event = _core.HilEvent()
    for index in range(seen, total):
        if _core.rb_hil_runner_event(state, index, ctypes.byref(event)):
            item = (event.step * DT, _core.HIL_EVENT_KINDS[event.kind], event.text.decode("utf-8", "replace"))
            events.append(item)
            if on_event is not None:
                on_event(*item)
    return events


def run_kpis(plant: _core.PlantParams, state) -> dict:
    """The KPIs of a MIL run (the same C accumulation, rb_run_accumulate) for the HIL run so far.
    The safety-timer trips are the external BCU's: unknown to the plant (None)."""
    k = _core.Kpis()
    _core.rb_hil_runner_kpis(ctypes.byref(plant), state, ctypes.byref(k))
    kpis = kpi_dict(k, plant.atmosphere)
    kpis["braked_distance_m"] = k.stopping_distance_m   # so far, also when the run was cut short
    kpis["safety_timer_trips"] = None
    return kpis


def run(scenario="emergency-300-heavy-rain", bcu: tuple[str, int] = ("127.0.0.1", 47800), cars: int | None = None,
        duration: float | None = None, hold_time: float = DEFAULT_HOLD_TIME, late_time: float = DEFAULT_LATE_TIME,
        record_interval: float | None = None, bind: tuple[str, int] = ("0.0.0.0", 0), paced: bool = True,
        priority: int = DEFAULT_PRIORITY, progress: Callable[[float, float], None] | None = None,
        on_event: Callable[[float, str, str], None] | None = None, kernel: str | None = None,
        on_start: Callable[[int, int, int], None] | None = None, key=None,
        on_rows: Callable[[np.ndarray], None] | None = None, stop: Callable[[], bool] | None = None,
        on_faults: Callable[[FaultSwitch], None] | None = None, chunk_steps: int = CHUNK_STEPS,
        on_live: Callable[[LiveView], None] | None = None, cpu: int | None = None) -> HilResult:
    """Run the plant of `scenario` against the BCU at `bcu` (host, port) until the stop or `duration` s
    (default: the scenario's max_time). progress(t, v) after each chunk; on_event(t, kind, text) for each
    watchdog event logged (malformed, late, lost, safe_on, safe_off, foreign, mismatch, forged, keyed,
    order); on_rows(rows) with each chunk's recorded rows (channels in the order of channels(cars))
    as soon as the chunk has run (a recording written as the run goes: railbrake.hil.mdf); stop()
    before each chunk: True ends the run as an interrupt does (a caller's signal handler that only
    notes the signal: raising from it can hit Python's import machinery, which swallows it);
    on_start(local port, session, configuration digest) once the plant's endpoint is open; on_faults(switch)
    then too, with the faults.FaultSwitch that injects and clears faults from any thread while the
    plant runs (refused once it has ended); on_live(view) then too, with the live.LiveView that reads
    the loop's latest step from any thread (a dashboard); chunk_steps: plant steps per C call (rows and progress
    come after each; a sequence follows the run closely with fewer); kernel: the
    plant's wheelset kernel, "auto" or "portable" (None: RAILBRAKE_KERNEL, else auto); key: the key
    file's path or its 16 bytes (the BCU's too: frames are authenticated). Ctrl-C or SIGTERM end the
    run early: the result holds what was recorded until then (interrupted=True). cpu: the CPU the loop
    has to itself within this process (None: wherever the OS puts it; docs/hil.md, live dashboard)."""
    if not 1 <= chunk_steps <= CHUNK_STEPS:
        raise InputError(f"chunk_steps = {chunk_steps}: must lie in [1, {CHUNK_STEPS}]")
    secret = key_bytes(key)
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    plant = plant_params(sc, n_cars, train=resolved.train, kernel=kernel)
    config = hil_config(sc, bcu_params(plant, sc, True, resolved.train), duration, hold_time, late_time,
                        record_interval, paced, secret)
    config.config = config_digest(sc, n_cars)
    names = channels(n_cars)
    state = ctypes.create_string_buffer(_core.rb_hil_runner_size())
    _core.call(_core.rb_hil_runner_open, ctypes.byref(plant), ctypes.byref(config), bind[0].encode(), bind[1],
               bcu[0].encode(), bcu[1], state)
    switch = FaultSwitch(state, n_cars, DT)
    if on_start is not None:
        on_start(_core.rb_hil_runner_port(state), config.session, config.config)
    if on_faults is not None:
        on_faults(switch)
    if on_live is not None:
        on_live(LiveView(state, plant.atmosphere))
    rows_per_chunk = chunk_steps // round(config.record_interval / DT) + 2
    chunk = np.zeros((rows_per_chunk, len(names)))
    chunks, events, seen = [], [], 0
    result = _core.HilResult()
    finished, rows = ctypes.c_int(0), ctypes.c_size_t(0)
    collecting = gc.isenabled()
    interrupted = False
    real_time = RealTime(False)
    gc.disable()   # a garbage collection between two chunks would delay the next step by milliseconds
    switch_interval = sys.getswitchinterval()
    sys.setswitchinterval(min(switch_interval, GIL_SWITCH_INTERVAL))
    try:
        with _normal_scheduling_after(), _sigterm_as_interrupt(), _own_cpu(cpu):
            real_time = request_real_time(priority) if paced else RealTime(False)
            while not finished.value and not interrupted:
                _core.call(_core.rb_hil_runner_advance, ctypes.byref(plant), ctypes.byref(config), state,
                           chunk_steps, _core.ptr(chunk), rows_per_chunk, ctypes.byref(rows), ctypes.byref(finished))
                chunks.append(chunk[:rows.value].copy())
                if on_rows is not None:
                    on_rows(chunks[-1])
                _core.rb_hil_runner_result(state, ctypes.byref(result))
                events += _drain_events(state, seen, result.events, on_event)
                seen = result.events
                if progress is not None and rows.value:
                    progress(result.time, float(chunk[rows.value - 1, 1]))
                interrupted = stop is not None and stop() and not finished.value
    except KeyboardInterrupt:
        # Ctrl-C or SIGTERM between two chunks (or inside Python code between them): keep what was
        # recorded; a chunk the interrupt cut short was not appended, the C state still holds it
        interrupted = True
        _core.rb_hil_runner_result(state, ctypes.byref(result))
        events += _drain_events(state, seen, result.events, None)
    finally:
        sys.setswitchinterval(switch_interval)
        switch.end()
        # before the close: the KPIs of what ran, also when interrupted; a forced run says so
        kpis = run_kpis(plant, state) | outside_validity_kpi(sc)
        _core.rb_hil_runner_close(state)
        if collecting:
            gc.enable()
    series = np.concatenate(chunks) if chunks else np.zeros((0, len(names)))
    outputs = {name: series[:, i].copy() for i, (name, _) in enumerate(names)}
    counters = {k: int(getattr(result, k)) for k in _core.HIL_COUNTERS}
    timing = {k: getattr(result, k) for k in _core.HIL_TIMING}
    timing["overruns"] = counters["overruns"]
    mismatch = None
    if result.mismatch:
        mismatch = (f"the BCU at {bcu[0]}:{bcu[1]} is set up for configuration 0x{result.bcu_config:08x} "
                    f"({result.bcu_cars} cars, {result.bcu_axles} axles); this plant runs "
                    f"{describe_config(sc, n_cars)}: start both with the same scenario, train and --cars")
    return HilResult(sc.name, n_cars, outputs["time"], outputs, dict(names), counters, timing, kpis, real_time,
                     events, plant.atmosphere, interrupted, mismatch, loss_dict(result), list(switch.changes))


# ------------------------------------------------------------------ the reference BCU

class BcuCounters(dict):
    """The reference BCU's counters (received, malformed, stale, sent, send_errors, cycles, foreign,
    refused, forged, challenges), with why it refused a plant (`refusal`, None if none) and whether Ctrl-C or SIGTERM
    ended it (`interrupted`)."""
    refusal: str | None = None
    interrupted: bool = False


def _refusal(state, scenario: Scenario, n_cars: int) -> str | None:
    config, cars, axles = ctypes.c_uint32(), ctypes.c_int(), ctypes.c_int()
    sender = ctypes.create_string_buffer(48)
    if not _core.rb_hil_bcu_refusal(state, ctypes.byref(config), ctypes.byref(cars), ctypes.byref(axles), sender,
                                    len(sender)):
        return None
    return (f"the plant at {sender.value.decode()} runs configuration 0x{config.value:08x} ({cars.value} cars, "
            f"{axles.value} axles); this BCU is set up for {describe_config(scenario, n_cars)}: its frames are "
            "refused")


def serve_bcu(scenario="emergency-300-heavy-rain", listen: tuple[str, int] = ("0.0.0.0", 47800),
              cars: int | None = None, duration: float = 0.0, idle_timeout: float = 2.0,
              priority: int = DEFAULT_BCU_PRIORITY, ready: Callable[[int, RealTime], None] | None = None,
              progress: Callable[[dict], None] | None = None,
              on_refusal: Callable[[str], None] | None = None, key=None) -> BcuCounters:
    """Serve plant frames with the scenario's BCU (same logic and demand profile as the simulation)
    until `duration` s of wall time (0: none) or `idle_timeout` s without a frame of its session
    (counted from the first datagram while none came). ready(port, real_time) once listening (port: the
    one bound, useful with port 0); on_refusal(text) once, when the first plant of another
    configuration is refused; key: the key file's path or its 16 bytes (the plant's too). Ctrl-C and
    SIGTERM end it with the counters. Returns the counters."""
    secret = key_bytes(key)
    if idle_timeout < 0 or duration < 0:
        raise InputError(f"idle_timeout = {idle_timeout}, duration = {duration}: must be >= 0")
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    bcu = bcu_params(plant_params(sc, n_cars, train=resolved.train), sc, True, resolved.train)
    wsp, spec = wsp_params(sc), _scenario_struct(sc)
    state = ctypes.create_string_buffer(_core.rb_hil_bcu_size())
    _core.call(_core.rb_hil_bcu_open, ctypes.byref(bcu), ctypes.byref(wsp), ctypes.byref(spec),
               config_digest(sc, n_cars), secret, secrets.token_bytes(_core.HIL_KEY_SIZE), listen[0].encode(),
               listen[1], state)
    counts = (ctypes.c_uint64 * len(_core.HIL_BCU_COUNTERS))()
    finished = ctypes.c_int(0)
    refusal, interrupted = None, False
    try:
        with _normal_scheduling_after(), _sigterm_as_interrupt():
            real_time = request_real_time(priority)
            if ready is not None:
                ready(_core.rb_hil_bcu_port(state), real_time)
            while not finished.value:
                _core.call(_core.rb_hil_bcu_serve, ctypes.byref(bcu), ctypes.byref(spec), state, BCU_CHUNK,
                           duration, idle_timeout, ctypes.byref(finished))
                _core.rb_hil_bcu_counters(state, counts)
                if refusal is None and (refusal := _refusal(state, sc, n_cars)) and on_refusal is not None:
                    on_refusal(refusal)
                if progress is not None:
                    progress(dict(zip(_core.HIL_BCU_COUNTERS, map(int, counts))))
    except KeyboardInterrupt:
        interrupted = True
    finally:
        _core.rb_hil_bcu_counters(state, counts)
        refusal = refusal or _refusal(state, sc, n_cars)
        _core.rb_hil_bcu_close(state)
    result = BcuCounters(zip(_core.HIL_BCU_COUNTERS, map(int, counts)))
    result.refusal, result.interrupted = refusal, interrupted
    return result

