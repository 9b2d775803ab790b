"""ASAM MDF4 recording of a HIL run (asammdf): every recorded channel with its SI unit; the
counters, the timing report, the KPIs and the run's provenance in the file comment
(railbrake.results.files.write_mdf, the same writer as `run --format mf4`).

While the run goes, the recording is an *unfinalised* MDF 4.10 file (ASAM MDF 4.1, identification
"UnFinMF ", the standard's way to record what may be cut short): asammdf writes its structure once,
then each chunk of rows is appended to its last data block with one write. Killed at any moment,
the file holds every chunk written before; MDF readers finalise such a file when they open it
(asammdf does: the length of the last DT block and the cycle count follow from the file's end).
At the end of the run the complete file (KPIs and counters in its comment) replaces it atomically."""

from __future__ import annotations

import json
import os
import struct
from pathlib import Path

import numpy as np

UNFINALISED_ID = b"UnFinMF "
# ID block: standard unfinalised flags at byte 60; bit 0: update the cycle counters of CG blocks,
# bit 2: update the length of the last DT block (ASAM MDF 4.1, the IDBLOCK)
UNFINALISED_FLAGS = 0b101
BLOCK_HEADER = struct.Struct("<4s4xQQ")   # id, length, link count


def _block(f, address: int) -> tuple[bytes, int, list[int]]:
    """id, length and links of the MDF4 block at address."""
    f.seek(address)
    block_id, length, links = BLOCK_HEADER.unpack(f.read(BLOCK_HEADER.size))
    return block_id, length, list(struct.unpack(f"<{links}Q", f.read(8 * links)))


class StreamingRecording:
    """An MDF4 recording that grows as the run goes: append(rows) after each chunk, then
    replace(...) with the complete file, or close() and leave the unfinalised one."""

    def __init__(self, path: Path, names: list[tuple[str, str]], comment: dict):
        from asammdf import MDF, Signal
        self.path = Path(path)
        channels = [name for name, _ in names if name != "time"]
        mdf = MDF(version="4.10")
        # one record whose values say where each channel sits in it (the master: time, 0)
        mdf.append([Signal(samples=np.array([float(i + 1)]), timestamps=np.zeros(1), name=name, unit=unit)
                    for i, (name, unit) in enumerate([c for c in names if c[0] != "time"])],
                   comment="railbrake HIL (recording in progress)")
        mdf.header.comment = json.dumps(comment)
        saved = Path(mdf.save(self.path, overwrite=True))
        mdf.close()
        self.path = saved
        self._columns = self._prepare(len(channels), [name for name, _ in names])

    def _prepare(self, n_channels: int, names: list[str]) -> np.ndarray:
        """Moves the data block, emptied, to the end of the file (where appends extend it) and marks
        the file unfinalised; returns, per field of a record, the column of the HIL rows it holds."""
        with open(self.path, "r+b") as f:
            _, _, hd_links = _block(f, 64)
            dg_address = hd_links[0]
            _, _, dg_links = _block(f, dg_address)
            cg_address, data_address = dg_links[1], dg_links[2]
            block_id, length, _ = _block(f, data_address)
            record = n_channels * 8 + 8
            if block_id != b"##DT" or length != BLOCK_HEADER.size + record:
                raise RuntimeError(f"{self.path}: asammdf laid the recording out unexpectedly "
                                   f"({block_id!r} of {length} bytes)")
            markers = np.frombuffer(f.read(record), dtype="<f8")
            # marker k + 1 is channel k of `names` without time; 0 is the master (time)
            others = [i for i, name in enumerate(names) if name != "time"]
            columns = np.array([names.index("time") if m == 0 else others[int(m) - 1] for m in markers])
            end = f.seek(0, os.SEEK_END)
            end += -end % 8   # blocks start on 8-byte boundaries
            f.truncate(end)
            f.seek(end)
            f.write(BLOCK_HEADER.pack(b"##DT", BLOCK_HEADER.size, 0))
            f.seek(dg_address + BLOCK_HEADER.size + 2 * 8)   # the DG's data link
            f.write(struct.pack("<Q", end))
            _, _, cg_links = _block(f, cg_address)
            f.seek(cg_address + BLOCK_HEADER.size + 8 * len(cg_links) + 8)   # after record_id: cycle count
            f.write(struct.pack("<Q", 0))
            f.seek(0)
            f.write(UNFINALISED_ID)
            f.seek(60)
            f.write(struct.pack("<H", UNFINALISED_FLAGS))
        self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        return columns

    def append(self, rows: np.ndarray) -> None:
        """Rows of the HIL channels (time first, as rb_hil_channel_info orders them): one write."""
        if len(rows) and self._fd is not None:
            os.write(self._fd, np.ascontiguousarray(rows[:, self._columns], dtype="<f8").tobytes())

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def recording_events(result, scenario=None) -> list[tuple[float, str, str]]:
    """(time s, name, comment) of what changed during the run, in time order: each fault the
    scenario schedules (fault_on at its start) and each injected or cleared live (fault_on,
    fault_off), each entry into and exit from the safe state (safe_on, safe_off), each change of the
    applied brake demand (at the recorded sample that first shows it) and the WSP trips the
    recording shows (railbrake.results.events.wsp_trips)."""
    from railbrake.results.channel_info import demand_text
    from railbrake.results.events import scheduled_faults, wsp_trips
    demand = np.asarray(result.outputs.get("brake_demand", []))
    changed = np.flatnonzero(np.diff(demand)) + 1
    events = [(float(result.time[i]), "demand", f"brake demand {demand_text(demand[i - 1])} -> "
               f"{demand_text(demand[i])}") for i in changed]
    events += [(c.time_s, f"fault_{'on' if c.action == 'inject' else 'off'}", f"{c.text} ({c.origin})")
              for c in getattr(result, "fault_changes", [])]
    events += safe_state_changes(result)
    events += scheduled_faults(scenario) if scenario is not None else []
    events += wsp_trips(result.time, result.outputs)
    return sorted(events, key=lambda e: e[0])


def safe_state_changes(result) -> list[tuple[float, str, str]]:
    """safe_on and safe_off from the loop's event log (the step and its reason), and from the
    recorded safe_state channel each change the log no longer holds (it keeps its latest
    entries only: a flood of late or malformed frames can push one out) at the recorded sample
    that first shows it."""
    logged = [(t, kind, text) for t, kind, text in result.events if kind in ("safe_on", "safe_off")]
    state = np.asarray(result.outputs.get("safe_state", []))
    time = np.asarray(result.time)
    interval = float(np.median(np.diff(time))) if len(time) > 1 else 0.0
    # the loop starts in the safe state until the first valid BCU frame, without a logged change
    recorded = [(float(time[0]), "safe_on", "safe state from the start, until the first valid BCU frame")] \
        if len(state) and state[0] else []
    for i in np.flatnonzero(np.diff(state)) + 1:
        kind = "safe_on" if state[i] else "safe_off"
        # logged at its step, recorded at the next sample: within one record interval before
        if not any(k == kind and time[i] - interval - 1e-9 <= t <= time[i] + 1e-9 for t, k, _ in logged):
            recorded.append((float(time[i]), kind, f"safe state {'entered' if state[i] else 'left'} (from the "
                             "recorded safe_state channel: the loop's event log no longer held it)"))
    return logged + recorded


def write_mdf(result, path: Path, scenario=None) -> Path:
    """Write result's channels (time base: the plant's simulated time, s) to an MDF 4.10 file; over
    an existing one (the streaming recording) only once the new one is complete."""
    from railbrake import scenario as scenarios
    from railbrake.results import files, record
    sc = scenario if scenario is not None else scenarios.load(result.scenario)
    path = Path(path)
    changes = getattr(result, "fault_changes", [])
    return files.write_mdf(record.from_hil(result, sc), path,
                              {"counters": result.counters, "timing": result.timing,
                               "interrupted": getattr(result, "interrupted", False),
                               "bcu_loss": getattr(result, "loss", None),
                               "fault_changes": [c.as_dict() for c in changes]},
                              events=recording_events(result, sc))   # whole, over the streaming one
