"""The documentation cannot drift from the code: an executed page (MyST-NB, `file_format: mystnb`)
quotes results only through its code cells and `glue`, so a figure the build computes is the
figure the page shows; every other page is listed in docs/CONVERSION.md as still carrying typed
figures. The API reference lists every public name (built here with `sphinx-build -t api`)."""

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[3] / "docs"
CONVERSION = DOCS / "CONVERSION.md"

# A number followed by a unit a result is given in: metres, seconds, bar, kilograms, megajoules,
# degrees Celsius, per cent, kilonewtons, tonnes, litres, m/s^2 (speeds, mostly inputs, are not).
RESULT = re.compile(r"(?<![\w.\-/])[-−+]?\d[\d,]*(?:\.\d+)?(?:\s*[-–/]\s*\d[\d,]*(?:\.\d+)?)*\s*"
                    r"(?:m|s|bar|kg|MJ|°C|%|kN|t|l|m/s²|m/s\^?2)(?![\w/])")
FENCE = re.compile(r"^(```+|:::+)\s*(\{?[\w-]*\}?)", re.M)
TYPED = re.compile(r"<!-- typed: [^>]*\S[^>]*-->.*?<!-- /typed -->", re.S)


def executed_pages() -> list[Path]:
    return sorted(p for p in DOCS.glob("*.md") if re.match(r"---\n(.*\n)*?file_format: mystnb\n", p.read_text()))


def listed_pages() -> set[str]:
    """The pages docs/CONVERSION.md lists as still carrying typed figures (`- docs/NAME.md`)."""
    return set(re.findall(r"^- `?docs/([\w.-]+\.md)`?", CONVERSION.read_text(encoding="utf-8"), re.M))


def prose(text: str) -> str:
    """The text a reader sees as typed: front matter, code cells, fenced YAML inputs, inline code,
    glue roles and `<!-- typed: why -->` regions (published data, design inputs) removed."""
    text = re.sub(r"\A---\n.*?\n---\n", "", text, flags=re.S)
    text = TYPED.sub("", text)
    out, fence = [], None
    for line in text.splitlines():
        m = FENCE.match(line)
        if fence is None and m:
            fence = (m[1], m[2])
            continue
        if fence is not None:
            if line.strip() == fence[0]:
                fence = None
            elif fence[1] not in ("{code-cell}", "yaml", "python", "sh", "{eval-rst}", "{toctree}"):
                out.append(line)    # a console block's output would be typed figures
            continue
        out.append(line)
    text = "\n".join(out)
    text = re.sub(r"\{glue(?::\w+)?\}`[^`]*`", "", text)
    text = re.sub(r"`[^`\n]*`", "", text)
    return re.sub(r"\]\([^)]*\)", "]", text)


def typed_figures(text: str) -> list[str]:
    return [m.group(0).strip() for m in RESULT.finditer(prose(text))]


def test_every_page_is_executed_or_listed_as_still_typed():
    """docs/CONVERSION.md lists exactly the pages not executed and those executed in part (a
    `<!-- typed: not yet converted ...-->` region)."""
    executed = {p.name for p in executed_pages()}
    others = {p.name for p in DOCS.glob("*.md")} - executed - {"CONVERSION.md", "index.md", "api.md"}
    partly = {p.name for p in executed_pages() if "<!-- typed: not yet converted" in p.read_text()}
    assert {"scripting.md", "vehicle.md", "simulation.md", "campaigns.md", "hil.md", "detailed.md", "pneumatics.md",
            "contact.md", "validation.md", "validation-cases.md", "hil-interface.md", "references.md"} <= executed
    assert listed_pages() == others | partly, "docs/CONVERSION.md must list exactly the pages not executed yet"


@pytest.mark.parametrize("page", executed_pages(), ids=lambda p: p.name)
def test_a_typed_marker_opening_a_line_holds_nothing_else(page):
    """A line that opens with `<!--` is a raw HTML block in Markdown: text after the marker on
    that line would be shown unparsed (roles, code spans)."""
    bad = [line for line in page.read_text().splitlines()
           if line.startswith("<!--") and not re.fullmatch(r"<!-- (typed: [^>]*|/typed) -->", line)]
    assert bad == []


@pytest.mark.parametrize("page", executed_pages(), ids=lambda p: p.name)
def test_an_executed_page_types_no_result_figure(page):
    """Every result in an executed page's prose comes from its cells (glue); a typed one would drift."""
    assert typed_figures(page.read_text(encoding="utf-8")) == []


def test_the_scan_finds_typed_figures_and_passes_glued_and_allowed_ones():
    page = ("---\nfile_format: mystnb\n---\nThe train stops in 5845 m after 78.4 s (−2.7 %), 3.84 bar g.\n"
            "It stops in {glue:text}`d:.0f` m from 300 km/h; `--v0-kmh 300` in 1 car.\n"
            "```console\n$ railbrake run\n2202.7 m\n```\n```{code-cell} ipython3\nx = 5 * 3  # 15 m\n```\n"
            "<!-- typed: published [P] -->\nmeasured 3760 m [P]\n<!-- /typed -->\n")
    assert typed_figures(page) == ["5845 m", "78.4 s", "−2.7 %", "3.84 bar", "2202.7 m"]


def _public_modules() -> dict[str, list[str]]:
    """railbrake and each subpackage with an __all__: module -> its public names."""
    import railbrake
    modules = {"railbrake": list(railbrake.__all__)}
    for path in sorted(Path(railbrake.__file__).parent.glob("*/__init__.py")):
        name = f"railbrake.{path.parent.name}"
        module = importlib.import_module(name)
        if hasattr(module, "__all__"):
            modules[name] = list(module.__all__)
    return modules


@pytest.mark.slow
def test_the_api_reference_lists_every_public_name(tmp_path):
    from sphinx.util.inventory import InventoryFile
    build = subprocess.run([sys.executable, "-m", "sphinx", "-q", "-W", "--keep-going", "-b", "html", "-t", "api",
                            "-d", str(tmp_path / "doctrees"), str(DOCS), str(tmp_path / "html")],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr[-3000:]
    with open(tmp_path / "html" / "objects.inv", "rb") as f:
        inventory = InventoryFile.load(f, "", lambda base, uri: uri)
    documented = {name for entries in inventory.values() for name in entries}
    modules = _public_modules()
    assert len(modules) >= 6
    missing = [f"{m}.{n}" for m, names in modules.items() for n in names if n != "__version__"
               and f"{m}.{n}" not in documented]
    assert missing == []
