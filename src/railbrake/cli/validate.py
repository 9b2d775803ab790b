"""`railbrake validate`: run the verification and validation cases, write the report."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from railbrake import atomic
from railbrake.cli._common import prepare_output, print_json, reports_errors
from railbrake.validation import load_cases, run_cases
from railbrake.validation import report as vreport
from railbrake.validation.runner import summary

STYLE = {"pass": "green", "fail": "red", "broken": "magenta"}


def register(app: typer.Typer) -> None:
    @app.command("validate")
    @reports_errors
    def validate(
        case: Optional[str] = typer.Option(None, "--case", help="Run only this case (its folder name)."),
        kind: Optional[str] = typer.Option(None, "--kind", help="verification, code-to-code or validation."),
        report: Optional[Path] = typer.Option(None, "--report", help="Write the HTML report here (plots embedded)."),
        markdown: Optional[Path] = typer.Option(None, "--markdown", help="Write the Markdown summary here."),
        cases: Optional[Path] = typer.Option(None, "--cases", help="Folder of cases (default: the repository's validation/)."),
        fast: bool = typer.Option(False, "--fast", help="Only the cases marked fast."),
        json: bool = typer.Option(False, "--json", help="Print the results as JSON."),
        strict: bool = typer.Option(False, "--strict", help="Exit 1 if a verification case fails or any case is broken."),
    ):
        """Run the cases: the models against analytic solutions, other codes and measurements."""
        found = load_cases(cases, case_id=case, kind=kind)
        console = Console(stderr=True)
        show = not json and console.is_terminal
        results = run_cases(found, fast_only=fast,
                            progress=(lambda cid, i, n: console.print(f"[{i + 1}/{n}] {cid}", end="\r")) if show else None)
        if report:
            atomic.write_text(prepare_output(report), vreport.to_html(results))
        if markdown:
            atomic.write_text(prepare_output(markdown), vreport.to_markdown(results))
        if json:
            print_json(vreport.as_json(results))
        else:
            _print_table(results, report, markdown)
        bad = [r for r in results if r.status == "broken" or (r.kind == "verification" and r.status != "pass")]
        if strict and bad:
            raise typer.Exit(code=1)


def _print_table(results, report, markdown) -> None:
    table = Table(title="railbrake validate")
    for column in ("case", "kind", "area", "difference", "tolerance", "result"):
        table.add_column(column, no_wrap=True)
    for r in results:
        unit = "%" if r.tolerance.endswith("%") else r.unit
        diff = "" if r.difference is None else f"{r.difference:.3g} {unit}"
        table.add_row(r.id, r.kind, r.area, diff, r.tolerance, f"[{STYLE[r.status]}]{r.status}[/]")
    console = Console(width=max(Console().width, 110))
    console.print(table)
    for r in results:
        if r.status != "pass":
            console.print(f"[{STYLE[r.status]}]{r.id}[/]: {r.reason}")
    counts = summary(results)
    console.print(f"{len(results)} cases: {counts['passed']} pass, {counts['failed']} fail, {counts['broken']} broken")
    for label, path in (("report", report), ("markdown", markdown)):
        if path:
            console.print(f"{label}: {path}")
