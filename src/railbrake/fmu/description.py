"""modelDescription.xml (FMI 2.0 and 3.0) and sources/buildDescription.xml of the plant's FMU,
written from the variable table (railbrake.fmu.variables)."""

from __future__ import annotations

import datetime
import os
from pathlib import Path
import math
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

from railbrake._version import __version__
from railbrake.fmu.variables import Unit, Variable, units


@dataclass(frozen=True)
class Header:
    """What the descriptions say besides the variables."""
    version: str            # FMI version, "2" or "3"
    identifier: str         # modelIdentifier: the binaries' file name, the FMI function prefix
    token: str              # GUID (FMI 2) / instantiationToken (FMI 3)
    title: str              # scenario and cars
    sources: tuple          # sources/*.c, in build order
    stop_time: float        # s, the scenario's longest run
    dt: float               # s, the plant's fixed step
    atmosphere: float       # Pa, the train's atmosphere (the bar_g display unit's zero)


AUTHOR = "the railbrake developers"
LICENSE = "Apache-2.0 (documentation/licenses/LICENSE.txt)"


def _attrs(**kw) -> str:
    return "".join(f" {k}={quoteattr(str(v))}" for k, v in kw.items() if v is not None)


def _number(x: float) -> str | None:
    return None if math.isinf(x) else repr(float(x))


def _start(v: Variable) -> str | None:
    if v.start is None:
        return None
    return ("true" if v.start else "false") if v.type == "Boolean" else repr(float(v.start))


def variability(v: Variable) -> str:
    if v.causality == "parameter":
        return "tunable" if v.tunable else "fixed"
    return "continuous" if v.type == "Real" else "discrete"


def _initial(v: Variable) -> str | None:
    return {"parameter": "exact", "output": "calculated"}.get(v.causality)


def _units(used: set, table: dict[str, Unit]) -> list[str]:
    lines = ["  <UnitDefinitions>"]
    for name in sorted(used):
        unit = table[name]
        displays = [f"<DisplayUnit{_attrs(name=d, factor=repr(f), offset=repr(o) if o else None)}/>"
                    for d, f, o in unit.displays]
        lines.append(f"    <Unit{_attrs(name=name)}><BaseUnit{_attrs(**unit.base)}/>{''.join(displays)}</Unit>")
    return lines + ["  </UnitDefinitions>"]


def _real_attrs(v: Variable, table: dict[str, Unit]) -> dict:
    settable = v.causality in ("parameter", "input")
    unit = table[v.unit] if v.unit else None
    return {"quantity": unit.quantity if unit else None, "unit": v.unit,
            "displayUnit": unit.default_display if unit else None, "start": _start(v),
            "min": _number(v.min) if settable else None, "max": _number(v.max) if settable else None}


def _variable_attrs(i: int, v: Variable) -> dict:
    """The attributes every FMI version shares (the value reference is the table position)."""
    return dict(name=v.name, valueReference=i, description=v.description or None, causality=v.causality,
                variability=None if v.causality == "independent" else variability(v), initial=_initial(v))


def _typed_attrs(v: Variable, table: dict[str, Unit]) -> dict:
    return _real_attrs(v, table) if v.type == "Real" else {"start": _start(v)}


def _fmi2_body(variables: list[Variable], fmu: Header, head: dict, table: dict) -> tuple[list, list, list]:
    lines = [f"<fmiModelDescription{_attrs(fmiVersion='2.0', guid=fmu.token, **head, numberOfEventIndicators='0')}>",
             f"  <CoSimulation{_attrs(**_co_simulation(fmu), canNotUseMemoryManagementFunctions='true')}>",
             "    <SourceFiles>", *[f"      <File{_attrs(name=s)}/>" for s in fmu.sources], "    </SourceFiles>",
             "  </CoSimulation>"]
    variable_lines = []
    for i, v in enumerate(variables):
        variable_lines += [f"    <ScalarVariable{_attrs(**_variable_attrs(i, v))}>",
                           f"      <{v.type}{_attrs(**_typed_attrs(v, table))}/>", "    </ScalarVariable>"]
    # ModelStructure indices are 1-based positions in ModelVariables
    unknowns = [f'      <Unknown index="{i + 1}"/>' for i, v in enumerate(variables) if v.causality == "output"]
    structure = ["    <Outputs>", *unknowns, "    </Outputs>", "    <InitialUnknowns>", *unknowns,
                 "    </InitialUnknowns>"]
    return lines, variable_lines, structure


def _fmi3_body(variables: list[Variable], fmu: Header, head: dict, table: dict) -> tuple[list, list, list]:
    lines = [f"<fmiModelDescription{_attrs(fmiVersion='3.0', instantiationToken=fmu.token, **head)}>",
             f"  <CoSimulation{_attrs(**_co_simulation(fmu), fixedInternalStepSize=repr(fmu.dt), hasEventMode='false')}/>"]
    variable_lines = [f"    <{'Float64' if v.type == 'Real' else 'Boolean'}"
                      f"{_attrs(**_variable_attrs(i, v), **_typed_attrs(v, table))}/>" for i, v in enumerate(variables)]
    outputs = [i for i, v in enumerate(variables) if v.causality == "output"]
    structure = ([f'    <Output valueReference="{i}"/>' for i in outputs]
                 + [f'    <InitialUnknown valueReference="{i}"/>' for i in outputs])
    return lines, variable_lines, structure


def _co_simulation(fmu: Header) -> dict:
    return dict(modelIdentifier=fmu.identifier, canHandleVariableCommunicationStepSize="true")


def generation_time(sources: Path | None = None) -> datetime.datetime:
    """When an FMU counts as generated, reproducibly (two exports of one configuration give the
    same bytes): $SOURCE_DATE_EPOCH (the reproducible-builds convention) if set, else the newest of
    the C sources it is built from (sources: their folder), else now."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch is not None and epoch.strip().isdigit():
        return datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc)
    if sources is not None and Path(sources).is_dir():
        newest = max((p.stat().st_mtime for p in Path(sources).rglob("*") if p.is_file()), default=None)
        if newest is not None:
            return datetime.datetime.fromtimestamp(int(newest), datetime.timezone.utc)
    return datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)


def model_description(fmu: Header, variables: list[Variable], generated: datetime.datetime | None = None) -> str:
    """modelDescription.xml in the FMI `fmu.version` ("2" or "3") flavour; generated: its
    generationDateAndTime (default: generation_time())."""
    stamp = (generated or generation_time()).strftime("%Y-%m-%dT%H:%M:%SZ")
    head = dict(modelName=fmu.identifier, description=f"railbrake real-time plant: {fmu.title}", author=AUTHOR,
                version=__version__, copyright=f"Copyright {AUTHOR}", license=LICENSE,
                generationTool=f"railbrake {__version__}", generationDateAndTime=stamp,
                variableNamingConvention="flat")
    table = units(fmu.atmosphere)
    if fmu.version == "2":
        lines, variable_lines, structure = _fmi2_body(variables, fmu, head, table)
    else:
        lines, variable_lines, structure = _fmi3_body(variables, fmu, head, table)
    experiment = _attrs(startTime="0", stopTime=repr(fmu.stop_time), stepSize=repr(fmu.dt))
    return "\n".join(['<?xml version="1.0" encoding="UTF-8"?>', *lines, *_units({v.unit for v in variables if v.unit}, table),
                      f"  <DefaultExperiment{experiment}/>", "  <ModelVariables>", *variable_lines,
                      "  </ModelVariables>", "  <ModelStructure>", *structure, "  </ModelStructure>",
                      "</fmiModelDescription>", ""])


def build_description(fmu: Header) -> str:
    """sources/buildDescription.xml (FMI 3): one C99 source set, headers found from sources/."""
    files = [f"      <SourceFile{_attrs(name=s)}/>" for s in fmu.sources]
    return "\n".join(['<?xml version="1.0" encoding="UTF-8"?>', '<fmiBuildDescription fmiVersion="3.0">',
                      f"  <BuildConfiguration{_attrs(modelIdentifier=fmu.identifier)}>",
                      '    <SourceFileSet language="C99">', *files, '      <IncludeDirectory name="."/>',
                      "    </SourceFileSet>", "  </BuildConfiguration>", "</fmiBuildDescription>", ""])
