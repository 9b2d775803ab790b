"""`railbrake run` and `railbrake bench`: the whole-train simulation and the plant's timing."""

from __future__ import annotations

import time
from pathlib import Path
from typing import List, Optional, Sequence

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from railbrake import simulation
from railbrake.cli import _common
from railbrake.cli._common import KERNEL_HELP, SET_HELP, prepare_folder, print_json, reports_errors
from railbrake.resolve import resolve
from railbrake.simulation.timing import DEFAULT_SCENARIO as BENCH_SCENARIO, SECONDS as BENCH_SECONDS
from railbrake.units import cars_text

DEFAULT_SCENARIO = "emergency-300-heavy-rain"



def warnings_for(result) -> list[str]:
    """What a brake engineer must not miss in a run (railbrake.results.kpis.warnings)."""
    from railbrake.results import kpis as info
    resolved = getattr(result, "resolved", None)
    working = None if resolved is None else resolved.train.spec.air_supply.min_working_bar
    return info.warnings(result.kpis, healthy_reference(result), working)


def healthy_reference(result) -> float | None:
    """The healthy brake's cylinder_shortfall_s a run's is judged on, when the run had one
    (simulation.response.healthy_shortfall: a short run, made only then)."""
    from railbrake.simulation import response
    return response.healthy_shortfall(result) if (result.kpis.get("cylinder_shortfall_s") or 0.0) > 0.0 else None


def run_scenario(scenario: str, cars: Optional[int], wsp: bool, out: Optional[Path], quiet: bool,
                 sets: Sequence[str] = (), axles: Optional[str] = None, window: Optional[str] = None,
                 formats: Optional[list] = None, kernel: Optional[str] = None):
    """Runs with a progress bar that appears once the run has lasted 2 s; writes the outputs
    (time series in `formats`, kpis.json, run.json, plots, report.html: railbrake.results)."""
    from railbrake.results import files, record
    resolved = resolve(scenario, cars, sets)
    sc = resolved.scenario
    formats = files.parse_formats(",".join(formats or []) or None)   # checked before the run
    record.parse_axles(axles, resolved.cars)
    record.parse_window(window)
    bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.fields[speed]}"),
                   TimeElapsedColumn(), console=Console(stderr=True), transient=True, disable=quiet)
    task = bar.add_task(sc.name, total=sc.spec.stop.max_time, speed="")
    start = time.monotonic()

    def progress(t, v):
        if not bar.live.is_started and time.monotonic() - start > 2.0:
            bar.start()
        bar.update(task, completed=t, speed=f"{3.6 * v:5.0f} km/h")

    try:
        result = simulation.run(resolved, wsp=wsp, progress=progress, kernel=kernel)
    finally:
        if bar.live.is_started:   # a bar never shown leaves no empty line on stderr
            bar.stop()
    healthy_reference(result)   # in result.meta, for the report's warnings
    if out is not None:
        from railbrake.results.outputs import write_outputs
        prepare_folder(out)
        from railbrake.results.events import run_events
        run_record = record.from_simulation(result, sc)
        write_outputs(run_record, out, formats, axles, window, mdf_events=run_events(sc, run_record),
                      resolved=resolved)
    return result


def measured_build_up(result, resolved):
    """EN 14531 ta, tb, te of the run's brake as measured on it (railbrake.simulation.response) and
    whether the WSP vented within the window, when the run starts braking at t = 0 and lasts the
    measurement's window (an InputError saying why when its brake force does not reach the first
    step's demand, on a slippery rail say); else None."""
    from railbrake.errors import InputError
    from railbrake.simulation import response
    first = resolved.scenario.spec.demand[0]
    braking = first.time == 0.0 and (first.emergency or first.service > 0.0)
    window = response.settings()["window_s"]
    if not braking or result.time.size < 2 or result.time[-1] < window:
        return None
    inside = result.time <= window
    wsp = any(result.outputs[n][inside].any() for n in result.outputs if n.startswith("vent_c"))
    try:
        return response.measure(result, resolved.train), wsp
    except InputError as exc:
        return exc


def print_build_up(measured) -> None:
    if isinstance(measured, Exception):
        typer.echo(f"build-up (EN 14531-1) not measured on this run: {measured}")
    elif measured is not None:
        b, wsp = measured
        lines = [f"build-up (EN 14531-1, measured on this run): ta {b.delay:.2f} s, tb {b.build_up:.2f} s, "
                 f"te {b.response:.2f} s;",
                 f"  cylinders filled (95 %) in {b.filling:.2f} s; largest jerk {b.jerk:.2f} m/s3"]
        if wsp:
            lines.append("  the WSP vented within it: not the brake's own build-up")
        typer.echo("\n".join(lines))   # each line within 80 columns


def print_kpis(result) -> None:
    table = Table(title=f"{result.scenario}: {cars_text(result.cars)}, WSP {'on' if result.wsp else 'off'}")
    table.add_column("KPI")
    table.add_column("value", justify="right")
    from railbrake.results import kpis as info
    for key, value in result.kpis.items():   # units and texts as in `hil` and report.html
        unit = info.unit(key) if value is not None else ""
        table.add_row(key, f"{info.text(value)} {unit if unit != '1' else ''}".strip())
    Console().print(table)


def print_warnings(result) -> None:
    """Each warning on one line of its own (not wrapped: a line per warning for grep and logs)."""
    for warning in warnings_for(result):
        typer.echo(f"warning: {warning}", err=True)


def register(app: typer.Typer) -> None:
    @app.command("run")
    @reports_errors
    def run(
        scenario: str = typer.Argument(DEFAULT_SCENARIO, autocompletion=_common.complete_scenario, help="Preset name or scenario YAML file."),
        cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
        no_wsp: bool = typer.Option(False, "--no-wsp", help="Run without wheel-slide protection."),
        out: Optional[Path] = typer.Option(None, help="Folder for the time series, kpis.json, plots and "
                                           "report.html."),
        json: bool = typer.Option(False, "--json", help="Print the KPIs as JSON."),
        axles: Optional[str] = typer.Option(None, help="Axles for WSP cycle plots besides the worst and "
                                            "faulty ones, e.g. c3a2,c1a1."),
        window: Optional[str] = typer.Option(None, help="T0:T1 in s for the WSP cycle plots (default: "
                                             "around each axle's first WSP activity)."),
        formats: Optional[List[str]] = typer.Option(None, "--format", help="Time series format(s): parquet, "
                                                    "csv, mf4 (repeat or comma-separate; default parquet)."),
        sets: list[str] = typer.Option([], "--set", help=SET_HELP),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
    ):
        """Whole-train brake simulation with WSP (default: 16 cars, emergency from 300 km/h in heavy rain)."""
        result = run_scenario(scenario, cars, not no_wsp, out, quiet=json, axles=axles, window=window,
                              formats=formats, sets=sets, kernel=kernel)
        print_warnings(result)
        build_up = measured_build_up(result, result.resolved)
        if json:
            print_json(result.kpis)
            return
        print_kpis(result)
        print_build_up(build_up)
        if out is not None:
            typer.echo(f"outputs: {out}/")

    @app.command("bench")
    @reports_errors
    def bench(
        scenario: str = typer.Argument(BENCH_SCENARIO, autocompletion=_common.complete_scenario, help="Preset name or scenario file."),
        cars: int = typer.Option(16, help="Number of cars."),
        kernel: Optional[str] = typer.Option(None, help=KERNEL_HELP),
        runs: Optional[int] = typer.Option(None, help="Timed runs (default: as many as fit in --seconds, "
                                           "at least 3)."),
        seconds: float = typer.Option(BENCH_SECONDS, help="Wall-clock time (s) the runs span when --runs "
                                      "is not given."),
        plant: bool = typer.Option(False, "--plant", help="The plant alone at 1 ms with constant inputs "
                                   "(the HIL step budget: p99 and max step times) instead of a whole run."),
        steps: int = typer.Option(20000, help="With --plant: plant steps per timed run (1 ms each)."),
        json: bool = typer.Option(False, "--json", help="Print as JSON."),
    ):
        """What a run costs: a whole run of SCENARIO (BCU, WSP, KPIs, no recording) in CPU us per
        simulated ms against its plant alone on the same inputs, and its real-time factor (wall
        clock). --plant: the plant's step times alone."""
        if plant:
            figures = simulation.bench_plant(cars, steps, kernel=kernel, runs=runs, seconds=seconds)
        else:
            figures = simulation.bench(scenario, cars, kernel=kernel, runs=runs, seconds=seconds)
        if json:
            print_json(figures)
        elif plant:
            typer.echo(f"{cars_text(figures['cars'])}, plant alone, {figures['kernel']} kernel, "
                       f"{figures['substeps']} sub-step(s), fastest of {figures['runs']} runs: step "
                       f"{figures['step_us_cpu_mean']:.2f} us CPU, {figures['step_us_wall_mean']:.2f} us wall "
                       f"({figures['realtime_factor']:.0f}x real time), {figures['step_us_p99']:.2f} us p99, "
                       f"{figures['step_us_max']:.2f} us max; over the runs {figures['realtime_factor_median']:.0f}x "
                       f"median, {figures['realtime_factor_slowest']:.0f}x slowest")
        else:
            typer.echo(f"{figures['scenario']}, {cars_text(figures['cars'])}, {figures['kernel']} kernel, "
                       f"{figures['simulated_s']:.1f} s simulated, fastest of {figures['runs']} runs:\n"
                       f"  whole run   {figures['run_cpu_us_per_ms']:.3f} us CPU per simulated ms "
                       f"(median {figures['run_cpu_us_per_ms_median']:.3f}), {figures['run_wall_s']:.2f} s wall, "
                       f"{figures['realtime_factor']:.0f}x real time\n"
                       f"  inside C    {figures['core_run_cpu_us_per_ms']:.3f} us CPU per simulated ms\n"
                       f"  plant alone {figures['plant_cpu_us_per_ms']:.3f} us CPU per simulated ms\n"
                       f"  ratio       {figures['ratio']:.2f} (whole run / plant alone; "
                       f"{figures['core_ratio']:.2f} inside C)")
