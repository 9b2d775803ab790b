"""The FMU's binaries as an integrator links them: only the FMI API exported, a modelIdentifier of
its own per configuration, two plants in one process (RTLD_GLOBAL) and in one statically linked
executable, each running as it does alone; no OS service and nothing beyond glibc 2.17."""

import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from railbrake import simulation
from railbrake.errors import InputError
from railbrake.fmu import export_fmu
from railbrake.fmu.binaries import FMI_HEADERS, exported_symbols, glibc_versions, have_zig
from railbrake.fmu.export import check_identifier

TWO_PLANTS = Path(__file__).with_name("two_plants.c")
SCENARIO = "emergency-250-dry"
SECONDS = 3.0
# What the plant may call from the C library: memory, strings, formatting of log messages, the
# <math.h> functions; nothing of the OS (clocks, files, threads, sockets).
C_LIBRARY = {"calloc", "free", "malloc", "memcpy", "memset", "memmove", "strcmp", "strlen", "snprintf",
             "vsnprintf", "__stack_chk_fail", "__cxa_finalize", "__memcpy_chk", "__memset_chk",
             "__snprintf_chk", "__vsnprintf_chk"}
MATH = {"exp", "log", "pow", "sqrt", "cbrt", "atan", "atan2", "tanh", "sin", "cos", "fabs", "floor", "ceil",
        "fmin", "fmax", "llround", "lround", "round", "exp2", "log10", "log1p", "expm1", "hypot", "fmod", "trunc"}


def unpack(path, folder):
    with zipfile.ZipFile(path) as zf:
        zf.extractall(folder)
    md = read_model_description(str(folder))
    return md, folder / "binaries"


def binary_of(path, folder, version):
    md, binaries = unpack(path, folder)
    platform = "linux64" if version == "2" else "x86_64-linux"
    return md, binaries / platform / f"{md.coSimulation.modelIdentifier}.so"


@pytest.fixture(scope="module")
def two_configurations(tmp_path_factory):
    """FMI 3 exports of the same scenario with 8 and 16 cars (the integrator's case: two trains in one
    real-time application): (folder, model description, cars) each."""
    out = []
    for cars in (8, 16):
        folder = tmp_path_factory.mktemp(f"cars{cars}")
        path = export_fmu(SCENARIO, folder / "plant.fmu", "3", cars=cars)
        md, _ = unpack(path, folder / "unzipped")
        out.append((folder / "unzipped", md, cars))
    return out


def test_only_the_fmi_api_is_exported(fmu, tmp_path):
    version, path = fmu
    _, binary = binary_of(path, tmp_path, version)
    done = subprocess.run(["nm", "-D", "--defined-only", str(binary)], capture_output=True, text=True, check=True)
    names = [line.split()[-1] for line in done.stdout.splitlines()]
    assert names and all(n.startswith(f"fmi{version}") for n in names), names
    assert set(exported_symbols(binary)) == set(names)


@pytest.mark.skipif(not have_zig(), reason="the zig toolchain (extra 'fmu', `make install`) builds the glibc "
                    "2.17 baseline; the system compiler links the host's glibc")
def test_linux_binary_needs_nothing_beyond_glibc_2_17(fmu, tmp_path):
    version, path = fmu
    _, binary = binary_of(path, tmp_path, version)
    dump = subprocess.run(["objdump", "-T", str(binary)], capture_output=True, text=True, check=True).stdout
    versions = glibc_versions(binary)
    assert versions and max(versions) <= (2, 17), dump
    undefined = {line.split()[-1] for line in dump.splitlines() if "*UND*" in line and "GLIBC" in line}
    assert undefined <= C_LIBRARY | MATH, undefined - C_LIBRARY - MATH


def test_model_identifier_per_configuration(two_configurations, tmp_path):
    (_, one, cars), (_, two, _) = two_configurations
    ids = {one.coSimulation.modelIdentifier, two.coSimulation.modelIdentifier}
    assert len(ids) == 2 and all(i.startswith("railbrake_emergency_250_dry_") for i in ids)
    again = export_fmu(SCENARIO, tmp_path / "again.fmu", "3", cars=cars, binary=False)
    assert read_model_description(str(again)).coSimulation.modelIdentifier == one.coSimulation.modelIdentifier
    given = export_fmu(SCENARIO, tmp_path / "given.fmu", "2", cars=1, binary=False, identifier="brake_hil_a")
    assert read_model_description(str(given)).coSimulation.modelIdentifier == "brake_hil_a"


@pytest.mark.parametrize("bad", ["1plant", "plant-8", "", "int", "_Reserved", "__x", "a" * 65, "pl ant"])
def test_model_identifier_must_be_a_c_identifier(bad):
    with pytest.raises(InputError, match="--model-identifier"):
        check_identifier(bad)


def _native(cars: int, vr_name: str, times):
    native = simulation.run(SCENARIO, cars=cars)
    rows = np.searchsorted(native.time, times - 1e-9)
    assert np.allclose(native.time[rows], times, atol=1e-9)
    return native.outputs[vr_name][rows]


def _check_two_plants(output: str, configurations):
    table = np.array([[float(x) for x in line.split()] for line in output.split("\n") if line])
    times = table[:, 0]
    assert times[-1] == pytest.approx(SECONDS)
    for column, (_, _, cars) in zip((1, 2), configurations):
        expected = _native(cars, f"cylinder_c{cars}a1", times)
        assert np.all(np.abs(table[:, column] - expected) <= 1e-9 * np.abs(expected)), column
    assert table[-1, 1] > 2e5 and table[-1, 2] > 2e5      # both braked (1 bar above atmospheric)


def _arguments(configurations):
    vrs = [next(v.valueReference for v in md.modelVariables if v.name == f"cylinder_c{cars}a1")
           for _, md, cars in configurations]
    return [md.instantiationToken for _, md, _ in configurations] + [str(v) for v in vrs] + [str(SECONDS)]


def test_two_plants_load_into_one_process_with_rtld_global(two_configurations, tmp_path):
    driver = tmp_path / "two_plants"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-isystem", str(FMI_HEADERS), str(TWO_PLANTS),
                    "-o", str(driver), "-ldl"], check=True)
    libraries = [str(folder / "binaries" / "x86_64-linux" / f"{md.coSimulation.modelIdentifier}.so")
                 for folder, md, _ in two_configurations]
    done = subprocess.run([str(driver), *libraries, *_arguments(two_configurations)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    _check_two_plants(done.stdout, two_configurations)


@pytest.mark.skipif(shutil.which("ld") is None or shutil.which("objcopy") is None, reason="needs binutils")
def test_two_plants_link_into_one_executable(two_configurations, tmp_path):
    """Each FMU's sources compiled with FMI3_FUNCTION_PREFIX = modelIdentifier_, partially linked
    into one object in which only the prefixed FMI functions stay global (docs/fmu.md's recipe)."""
    objects, prefixes = [], []
    for folder, md, _ in two_configurations:
        identifier = md.coSimulation.modelIdentifier
        work = tmp_path / identifier
        work.mkdir()
        sources = sorted(str(p) for p in (folder / "sources").glob("*.c"))
        subprocess.run(["cc", "-std=c99", "-O2", "-ffp-contract=off", "-c",
                        f"-DFMI3_FUNCTION_PREFIX={identifier}_", f"-I{folder / 'sources'}", "-isystem",
                        str(FMI_HEADERS), *sources], check=True, cwd=work)
        combined = tmp_path / f"{identifier}.o"
        subprocess.run(["ld", "-r", "-o", str(combined), *sorted(str(p) for p in work.glob("*.o"))], check=True)
        subprocess.run(["objcopy", "--wildcard", f"--keep-global-symbol={identifier}_fmi3*", str(combined)],
                       check=True)
        objects.append(str(combined))
        prefixes.append(f"{identifier}_")
    driver = tmp_path / "two_plants_static"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", f"-DPREFIX_A={prefixes[0]}",
                    f"-DPREFIX_B={prefixes[1]}", "-isystem", str(FMI_HEADERS), str(TWO_PLANTS), *objects,
                    "-o", str(driver), "-lm"], check=True)
    done = subprocess.run([str(driver), *_arguments(two_configurations)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    _check_two_plants(done.stdout, two_configurations)
