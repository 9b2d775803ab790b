"""`railbrake config show`: the fully resolved configuration a run uses (scenario + train)."""

from __future__ import annotations

from typing import Optional

import typer
import yaml

from railbrake.cli import _common
from railbrake.cli._common import print_json, reports_errors
from railbrake.cli.simulation import DEFAULT_SCENARIO, SET_HELP
from railbrake.resolve import resolve

app = typer.Typer(help="The resolved configuration: every key a run uses, with its units.", no_args_is_help=True)


@app.command("show")
@reports_errors
def show(
    scenario: str = typer.Argument(DEFAULT_SCENARIO, autocompletion=_common.complete_scenario, help="Preset name or scenario YAML file."),
    cars: Optional[int] = typer.Option(None, help="Number of cars (default: the scenario's train)."),
    sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    json: bool = typer.Option(False, "--json", help="Print as JSON."),
    keys: bool = typer.Option(False, "--keys", help="List the dotted keys --set accepts instead."),
):
    """Print the scenario and its train as a run resolves them (file units), after --cars and --set."""
    resolved = resolve(scenario, cars, sets)
    if keys:
        for key in resolved.keys():
            typer.echo(key)
        return
    tree = resolved.tree()
    if json:
        print_json({"digest": resolved.digest(), "config": tree})
        return
    typer.echo(f"# {resolved.name}: {resolved.cars} cars, train {tree['train'].get('name', '')} "
               f"({tree['train'].get('load_case', '')} load); digest {resolved.digest()[:16]}")
    typer.echo("# units as in the files: in the value ('300 km/h') or in the key (tare_t: t, "
               "*_bar: bar gauge, *_mm2: mm^2, *_l: litres)")
    typer.echo(yaml.safe_dump(tree, sort_keys=False, allow_unicode=True, width=100).rstrip())
