"""`railbrake hil` (the plant paced at 1 kHz against a BCU over UDP) and `railbrake bcu` (the reference BCU)."""

from __future__ import annotations

import ipaddress

import signal
import sys
import time
from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from railbrake import hil as hil_runner
from railbrake.cli import _common
from railbrake.cli._common import KERNEL_HELP, SET_HELP, prepare_output, print_json, reports_errors
from railbrake.errors import InputError
from railbrake.hil.keys import read_key, write_key
from railbrake.resolve import resolve
from railbrake.units import cars_text, ms_to_kmh

DEFAULT_SCENARIO = "emergency-300-heavy-rain"
EVENTS_SHOWN = 20   # watchdog events echoed to stderr; the counters hold them all
EXIT_BCU_LOST = 3   # the run went on without its BCU (safe state): docs/hil.md
KEY_HELP = ("Key file shared by plant and BCU (one line of 32 hex digits, mode 600; `railbrake hil-key FILE` "
            "makes one): every frame is authenticated with it.")


def _event_printer(err: Console):
    shown = 0

    def on_event(t, kind, text):
        nonlocal shown
        shown += 1
        if shown <= EVENTS_SHOWN:
            err.print(f"[yellow]watchdog[/] t = {t:.3f} s {kind}: {text}", highlight=False)
        elif shown == EVENTS_SHOWN + 1:
            err.print("[yellow]watchdog[/] further events are only counted", highlight=False)
    return on_event


class _Interrupts:
    """SIGINT and SIGTERM for `railbrake hil`, from the command's start: each is only noted (raising
    from a handler can land in Python's import machinery, which swallows the exception and prints a
    traceback); the run stops before its next chunk once one came, and the recording and the summary
    are always written (a second Ctrl-C never loses what the first kept)."""

    def __init__(self, err: Console):
        self.err, self.count, self.finishing = err, 0, False
        self.previous = {}

    def __call__(self, signum, frame):
        self.count += 1
        if self.count > 1 or self.finishing:
            self.err.print("interrupt noted: writing the recording and the summary first", highlight=False)

    def stop(self) -> bool:
        return self.count > 0

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            self.previous[sig] = signal.signal(sig, self)
        return self

    def __exit__(self, *exc):
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        return False


def _print_report(result) -> None:
    console = Console()
    table = Table(title=f"HIL {result.scenario}, {cars_text(result.cars)}, {result.time[-1]:.1f} s")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    from railbrake.results import kpis as info
    k = result.kpis
    what = "stopping" if k["stopped"] else "braking (no stop yet)"
    table.add_row(f"{what} distance", f"{k['braked_distance_m']:.1f} m")
    if k["stopping_time_s"] is not None:
        table.add_row(f"{what} time", f"{k['stopping_time_s']:.2f} s")
    shown = ("stopping_distance_m", "braked_distance_m", "stopping_time_s", "stopped")
    for key, value in k.items():   # the other KPIs, as `railbrake run` reports them
        if key not in shown and value is not None:
            unit = info.unit(key)
            table.add_row(key, f"{info.text(value)} {unit if unit != '1' else ''}".strip())
    for key, value in result.counters.items():
        table.add_row(key.replace("_", " "), str(value))
    console.print(table)
    for line in result.timing_report():
        console.print(line, highlight=False)


def parse_control(text: str | None, option: str = "--control") -> tuple[str, int] | None:
    """'[HOST:]PORT' (host default 127.0.0.1; port 0: any free one) -> (host, port)."""
    if text is None:
        return None
    host, _, port = text.rpartition(":")
    if not port.isascii() or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise InputError(f"{option} = {text!r}: port = {port!r}: expected [HOST:]PORT, port in [0, 65535]")
    if host and host.replace(".", "").isdigit():
        try:
            ipaddress.IPv4Address(host)
        except ValueError:
            raise InputError(f"{option} = {text!r}: host = {host!r}: expected an IPv4 address a.b.c.d (four "
                             "numbers 0-255) or a host name") from None
    return host or "127.0.0.1", int(port)


class _Control:
    """The control socket of --control and the dashboard of --dashboard, started once the plant runs
    (on_faults, on_live), stopped after."""

    def __init__(self, address, dashboard, cars: int, err: Console):
        self.address, self.err, self.server, self.board = address, err, None, None
        if dashboard is not None:
            from railbrake.hil.dashboard import Dashboard
            self.board = Dashboard(*dashboard, cars=cars)
            err.print(f"dashboard on {self.board.url}", highlight=False, soft_wrap=True)

    def start(self, switch) -> None:
        if self.board is not None:
            self.board.attach(switch=switch)
        if self.address is None:
            return
        from railbrake.hil.control import ControlServer
        self.server = ControlServer(switch, *self.address, token=self.board.token if self.board else None)
        self.err.print(f"control on tcp://{self.server.host}:{self.server.port}, token {self.server.token} "
                       "(docs/hil.md, faults at run time)", highlight=False, soft_wrap=True)

    def live(self, view) -> None:
        if self.board is not None:
            self.board.attach(view=view)

    def stop_requested(self) -> bool:
        return self.board is not None and self.board.stop_requested()

    def stop(self) -> None:
        if self.server is not None:
            self.server.stop()
        if self.board is not None:
            self.board.close()


def _run(resolved, peer, secret, record, bcu, local, err, json, control=None, dashboard=None, **options):
    """The paced run with its progress bar; with --record, the recording grows chunk by chunk as the
    run goes (railbrake.hil.mdf: what was written survives a kill); with --control, the control
    socket takes fault changes while the plant runs."""
    sc = resolved.scenario
    control = _Control(control, dashboard, resolved.cars, err)
    if dashboard is not None and options.get("cpu") is None:
        err.print("note: the dashboard's server threads share the loop's CPU; --cpu N gives the loop one to "
                  "itself (docs/hil.md)", highlight=False, soft_wrap=True)
    interrupted = options.pop("stop")
    stream = None
    if record is not None:
        from railbrake.hil.mdf import StreamingRecording
        stream = StreamingRecording(record, hil_runner.channels(resolved.cars),
                                    {"scenario": sc.name, "cars": resolved.cars,
                                     "recording": "unfinalised: written as the run went, which did not end"})
    total = sc.spec.stop.max_time if options["duration"] is None else options["duration"]
    bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.fields[speed]}"),
                   TimeElapsedColumn(), console=err, transient=True, disable=json,
                   refresh_per_second=2)   # the render thread competes for the GIL between chunks
    task = bar.add_task(f"HIL {sc.name}", total=total, speed="")
    try:
        with bar:
            result = hil_runner.run(
                resolved, peer, bind=local, on_event=_event_printer(err), key=secret,
                on_rows=stream.append if stream is not None else None,
                on_start=lambda port, session, config: err.print(
                    f"plant on udp://{local[0]}:{port}, session 0x{session:08x}, configuration 0x{config:08x}, "
                    f"BCU {bcu}", highlight=False, soft_wrap=True),
                progress=lambda t, v: bar.update(task, completed=t, speed=f"{ms_to_kmh(v):5.0f} km/h"),
                on_faults=control.start, on_live=control.live,
                stop=lambda: interrupted() or control.stop_requested(), **options)
    finally:
        control.stop()
        if stream is not None:
            stream.close()
    return result


def _summary(result, json: bool, written, out, bcu: str) -> None:
    """Why the run went as it did (stderr), then the report: JSON or the table."""
    err = Console(stderr=True)
    if result.mismatch:
        err.print(f"[red]error[/]: {result.mismatch}", highlight=False)
    elif result.counters["received"] == 0:
        err.print(f"[red]error[/]: no frame came from the BCU at {bcu}: the safe state applied throughout",
                  highlight=False)
    if not result.mismatch and result.loss_report():
        err.print(f"[red]error[/]: {result.loss_report()}", highlight=False, soft_wrap=True)
    if result.interrupted:
        err.print(f"interrupted at t = {result.time[-1] if len(result.time) else 0.0:.3f} s: "
                  "the recording and counters hold the run until then", highlight=False)
    for change in result.fault_changes:
        err.print(f"fault t = {change.time_s:.3f} s: {change.text} ({change.origin})", highlight=False)
    if json:
        print_json({"scenario": result.scenario, "cars": result.cars, "kpis": result.kpis,
                    "counters": result.counters, "timing": result.timing, "bcu_loss": result.loss,
                    "fault_changes": [c.as_dict() for c in result.fault_changes],
                    "events": [{"time": t, "kind": kind, "text": text} for t, kind, text in result.events],
                    "real_time": {"memory_locked": result.real_time.memory_locked,
                                  "fifo_priority": result.real_time.fifo_priority,
                                  "notes": result.real_time.notes()}})
    else:
        _print_report(result)
    if written is not None:
        typer.echo(f"recording: {written}", err=json)
    if out is not None:
        typer.echo(f"outputs: {out}/", err=json)


def _prepare_and_run(interrupts, scenario, bcu, key, cars, duration, record, record_interval, hold_time,
                     late_time, bind, priority, json, sets, out, axles, window, formats, kernel, control,
                     dashboard, cpu):
    """Everything `railbrake hil` does, with its interrupts noted: inputs checked, the run, then the
    recording, the run folder and the summary, whatever interrupts come."""
    from railbrake.results import files, record as records
    formats = files.parse_formats(",".join(formats or []) or "mf4")   # checked before the run
    peer = hil_runner.parse_udp_url(bcu, "--bcu")
    secret = read_key(key)
    local = hil_runner.parse_udp_url(bind, "--bind", allow_any_port=True)
    control = parse_control(control)
    dashboard = parse_control(dashboard, "--dashboard")
    if duration is not None and duration <= 0:
        raise InputError(f"--duration = {duration}: must be > 0 s")
    resolved = resolve(scenario, cars, sets)
    sc = resolved.scenario
    records.parse_axles(axles, resolved.cars)
    records.parse_window(window)
    prepare_output(record, "--record", (".mf4", ".mdf"))   # before the run, which cannot be repeated
    err = Console(stderr=True)
    if interrupts.stop():
        err.print("interrupted before the run started", highlight=False)
        raise typer.Exit(code=130)
    result = _run(resolved, peer, secret, record, bcu, local, err, json, duration=duration, hold_time=hold_time,
                  late_time=late_time, record_interval=record_interval, priority=priority, kernel=kernel,
                  stop=interrupts.stop, control=control, dashboard=dashboard, cpu=cpu)
    interrupts.finishing = True
    written = None
    if record is not None:
        from railbrake.hil.mdf import write_mdf
        written = write_mdf(result, record, sc)
    if out is not None:
        from railbrake.hil.mdf import recording_events
        from railbrake.results.outputs import write_outputs
        write_outputs(records.from_hil(result, sc), out, formats, axles, window,
                      mdf_extra={"counters": result.counters, "timing": result.timing,
                                 "fault_changes": [c.as_dict() for c in result.fault_changes]},
                      mdf_events=recording_events(result, sc))
    _summary(result, json, written, out, bcu)
    return result


def register(app: typer.Typer) -> None:
    @app.command("hil")
    @reports_errors
    def hil(
        scenario: str = typer.Argument(DEFAULT_SCENARIO, autocompletion=_common.complete_scenario, help="Preset name or scenario YAML file."),
        bcu: str = typer.Option(..., "--bcu", help="The BCU's address, udp://HOST:PORT."),
        key: Path = typer.Option(..., "--key", help=KEY_HELP),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        duration: Optional[float] = typer.Option(None, help="s; default: the scenario's max_time (the run also "
                                                 "ends at the stop)."),
        record: Optional[Path] = typer.Option(None, "--record", help="Write the channels to this MDF4 file."),
        record_interval: Optional[float] = typer.Option(None, help="s between recorded samples, a multiple of "
                                                        "1 ms (default: the scenario's)."),
        hold_time: float = typer.Option(hil_runner.DEFAULT_HOLD_TIME, help="s the last BCU commands are held "
                                        "before the safe state."),
        late_time: float = typer.Option(hil_runner.DEFAULT_LATE_TIME, help="s: a BCU frame answering an older "
                                        "plant step is late (counted, not applied)."),
        bind: str = typer.Option("udp://0.0.0.0:0", help="Local address of the plant, udp://HOST:PORT (0: any)."),
        priority: int = typer.Option(hil_runner.DEFAULT_PRIORITY, help="SCHED_FIFO priority to ask for (0: none)."),
        json: bool = typer.Option(False, "--json", help="Print counters, timing and KPIs as JSON."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
        out: Optional[Path] = typer.Option(None, help="Folder for the time series, kpis.json, plots and "
                                           "report.html (as `run --out`)."),
        axles: Optional[str] = typer.Option(None, help="With --out: axles for WSP cycle plots besides the "
                                            "worst and faulty ones, e.g. c3a2."),
        window: Optional[str] = typer.Option(None, help="With --out: T0:T1 in s for the WSP cycle plots."),
        formats: Optional[List[str]] = typer.Option(None, "--format", help="With --out: time series format(s): "
                                                    "mf4, parquet, csv (default mf4)."),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
        control: Optional[str] = typer.Option(None, "--control", help="[HOST:]PORT of a control socket taking "
                                              "fault changes while the plant runs (JSON lines with the token "
                                              "printed at the start; host default 127.0.0.1; port 0: any)."),
        dashboard: Optional[str] = typer.Option(None, "--dashboard", help="[HOST:]PORT of a live web page of the "
                                                "run (host default 127.0.0.1; elsewhere only with the token of "
                                                "the URL printed at the start; port 0: any)."),
        cpu: Optional[int] = typer.Option(None, "--cpu", help="The CPU the 1 ms loop has to itself: the "
                                          "process's other threads (dashboard, control socket) are kept off "
                                          "it (default: wherever the OS puts it)."),
    ):
        """The plant paced at 1 kHz on the wall clock, exchanging frames with a BCU over UDP (docs/hil.md)."""
        with _Interrupts(Console(stderr=True)) as interrupts:
            result = _prepare_and_run(interrupts, scenario, bcu, key, cars, duration, record, record_interval,
                                      hold_time, late_time, bind, priority, json, sets, out, axles, window,
                                      formats, kernel, control, dashboard, cpu)
        if result.interrupted:
            raise typer.Exit(code=130)
        if result.mismatch:
            raise typer.Exit(code=1)
        if result.loss.get("lost"):
            raise typer.Exit(code=EXIT_BCU_LOST)

    @app.command("hil-key")
    @reports_errors
    def hil_key(path: Path = typer.Argument(..., help="The key file to create (mode 600; never overwritten).")):
        """A new random key file for `hil --key` and `bcu --key` (give both the same file)."""
        typer.echo(f"key file: {write_key(path)}")

    @app.command("bcu")
    @reports_errors
    def bcu(
        scenario: str = typer.Argument(DEFAULT_SCENARIO, autocompletion=_common.complete_scenario, help="Preset name or scenario YAML file (demand profile, "
                                       "train)."),
        listen: str = typer.Option(..., "--listen", help="Address to listen on, udp://HOST:PORT (port 0: any, "
                                   "printed)."),
        key: Path = typer.Option(..., "--key", help=KEY_HELP),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        duration: float = typer.Option(0.0, help="s of wall time, then stop (0: no limit)."),
        idle_timeout: float = typer.Option(2.0, help="s without plant frames, after the first, then stop."),
        priority: int = typer.Option(hil_runner.DEFAULT_BCU_PRIORITY, help="SCHED_FIFO priority to ask for (0: "
                                     "none); below the plant's 80 by default."),
        json: bool = typer.Option(False, "--json", help="Print the counters as JSON at the end."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    ):
        """The reference BCU: the simulation's BCU and WSP logic answering plant frames over UDP."""
        host, port = hil_runner.parse_udp_url(listen, "--listen", allow_any_port=True)
        secret = read_key(key)
        err = Console(stderr=True)

        def ready(bound, real_time):
            # First line of stdout: scripts (and the tests) read the port from it.
            sys.stdout.write(f"listening on udp://{host}:{bound}\n")
            sys.stdout.flush()
            for note in real_time.notes() if real_time.requested else []:
                err.print(f"note: {note}", highlight=False)

        def refused(text):
            err.print(f"[red]error[/]: {text}", highlight=False)   # once: later refusals only counted

        start = time.monotonic()
        counters = hil_runner.serve_bcu(resolve(scenario, cars, sets), (host, port), duration=duration,
                                        idle_timeout=idle_timeout, priority=priority, ready=ready,
                                        on_refusal=refused, key=secret)
        if json:
            print_json(dict(counters))
        else:
            typer.echo(f"served {time.monotonic() - start:.1f} s: " +
                       ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in counters.items()))
        if counters.interrupted:
            err.print("interrupted: the counters above hold the run until then", highlight=False)
            raise typer.Exit(code=130)
        if counters.refusal and counters["received"] == 0:
            raise typer.Exit(code=1)   # set up for another plant: served nothing
