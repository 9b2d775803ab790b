"""`railbrake train new`: a commented train file to start a train of one's own from."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from railbrake import atomic
from railbrake.cli import _common
from railbrake.cli._common import prepare_output, reports_errors

app = typer.Typer(help="Train files: a commented template to start from.", no_args_is_help=True)


@app.command("new")
@reports_errors
def new(
    preset: str = typer.Option(..., "--from", autocompletion=_common.complete_train, help="Train preset (or train file) to start from."),
    name: Optional[str] = typer.Option(None, help="The new train's name (default: my-PRESET)."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here (.yaml; default: stdout)."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing output file."),
    cars: Optional[int] = typer.Option(None, help="Number of cars (the preset's formation repeated and cut)."),
    formation: Optional[str] = typer.Option(None, help="Car types in order, comma-separated, e.g. "
                                            "trailer,motor,motor,trailer (the preset's car_types)."),
    max_speed: Optional[float] = typer.Option(None, "--max-speed", help="Top speed, km/h."),
):
    """Write a train file from a preset, with what each value may be as comments."""
    from railbrake.errors import InputError
    from railbrake.train_template import template
    text = template(preset, name, cars, formation, max_speed)
    if output is None:
        typer.echo(text, nl=False)
        return
    prepare_output(output, "--output", (".yaml", ".yml"))
    if output.exists() and not force:
        raise InputError(f"--output {output}: exists; choose another name or add --force")
    atomic.write_text(output, text)
    typer.echo(f"train file: {output} (use it as train: {{preset: {output}}} in a scenario)")


def register(root: typer.Typer) -> None:
    root.add_typer(app, name="train")
