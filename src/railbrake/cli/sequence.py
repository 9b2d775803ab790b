"""`railbrake sequence run|list`: test sequences (railbrake.sequence/1) with verdicts, JUnit XML and HTML."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console

from railbrake.cli import _common
from railbrake.cli._common import SET_HELP, prepare_output, reports_errors
from railbrake.errors import InputError

app = typer.Typer(help="Test sequences (railbrake.sequence/1): steps, expectations, verdicts (docs/sequences.md).",
                  no_args_is_help=True)
EXIT_FAILED = 1   # a test failed or erred; bad input: 2 (reports_errors)


@app.command("list")
@reports_errors
def list_presets():
    """The shipped sequence presets."""
    from railbrake import sequence
    for name in sequence.presets():
        typer.echo(name)


@app.command("run")
@reports_errors
def run(
    source: str = typer.Argument(..., autocompletion=_common.complete_sequence, help="A sequence file or a shipped preset (`railbrake sequence list`)."),
    junit: Optional[Path] = typer.Option(None, "--junit", help="Write the verdicts as JUnit XML here."),
    html: Optional[Path] = typer.Option(None, "--html", help="Write the HTML report (plots of each "
                                        "expectation's window) here."),
    bcu: Optional[str] = typer.Option(None, "--bcu", help="udp://HOST:PORT of a BCU: run against the paced HIL "
                                      "loop (default: the MIL plant with the reference BCU's logic)."),
    key: Optional[Path] = typer.Option(None, "--key", help="With --bcu: the HIL key file (as `railbrake hil --key`)."),
    sets: list[str] = typer.Option([], "--set", help=SET_HELP),
):
    """Run every test of a sequence against the plant; exit status 0 when all pass, 1 otherwise."""
    from railbrake import sequence
    from railbrake.sequence import engine, reports
    from railbrake import hil
    from railbrake.hil.keys import read_key
    peer = hil.parse_udp_url(bcu, "--bcu") if bcu is not None else None
    if (peer is None) != (key is None):
        raise InputError("--bcu and --key go together: the HIL link is authenticated (docs/hil.md)")
    secret = read_key(key) if key is not None else None
    prepare_output(junit, "--junit", (".xml",))
    prepare_output(html, "--html", (".html", ".htm"))
    seq = sequence.load(source)
    console = Console()

    def progress(test, step):
        colour = {"pass": "green", "fail": "red", "error": "red"}.get(step.verdict, "default")
        console.print(f"{test} step {step.index + 1} t = {step.start_s:8.3f} s [{colour}]{step.verdict:5}[/] "
                      f"{step.message}", highlight=False, soft_wrap=True)

    results = engine.run(seq, sets, progress, peer, secret)
    for result in results:
        colour = "green" if result.verdict == "pass" else "red"
        console.print(f"[bold]{result.name}[/]: [{colour}]{result.verdict.upper()}[/]", highlight=False)
    for path in reports.write(seq, results, "MIL" if peer is None else f"HIL against {bcu}", junit, html):
        typer.echo(f"report: {path}")
    if any(r.verdict != "pass" for r in results):
        raise typer.Exit(code=EXIT_FAILED)
