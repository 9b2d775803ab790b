"""What each recorded channel is, for readers of a recording (MDF4 channel comments), and the
states of the integer channels (MDF4 value-to-text conversions). By base name: the _cN / _cNaK
suffix names the car and axle (1-based)."""

from __future__ import annotations

import re

COMMENTS = {
    "speed": "train speed (the cars' mean)",
    "position": "distance run from the start",
    "deceleration": "train deceleration, positive when braking",
    "demand_deceleration": "deceleration the BCU demands",
    "main_reservoir": "main reservoir pressure, absolute",
    "pipe_end": "main reservoir pipe pressure at the last car, absolute",
    "compressor_on": "compressor running",
    "air_vented": "air mass vented to the atmosphere so far",
    "air_drawn": "air mass drawn from the main reservoir so far",
    "supply": "supply reservoir pressure of the car, absolute",
    "pilot": "EP valve pilot pressure of the car, absolute",
    "relay": "relay valve output pressure of the car, absolute",
    "ed_force": "electrodynamic brake force of the car",
    "pressure_demand": "cylinder pressure demand applied to the car, absolute",
    "wheel_speed": "wheelset circumferential speed",
    "slip": "wheelset slip (wheel speed - train speed) / train speed",
    "cylinder": "brake cylinder pressure of the wheelset, absolute",
    "hold": "WSP hold valve state of the wheelset",
    "vent": "WSP vent valve state of the wheelset",
    "adhesion": "adhesion coefficient used by the wheelset",
    "disc_temperature": "brake disc temperature of the wheelset",
    "brake_energy": "friction brake energy of the wheelset so far",
    "wsp_mode": "state of the BCU's WSP on the wheelset (4, 5: its safety timer tripped)",
    "brake_demand": "brake demand applied by the plant",
    "safe_state": "HIL watchdog state",
    "bcu_frames": "valid BCU frames received so far",
}

# integer channels: value -> text (MDF4 value-to-text conversion)
STATES = {
    "hold": {0: "open (passes air)", 1: "energised: closed (holds)"},
    "vent": {0: "shut", 1: "energised: open (vents)"},
    "compressor_on": {0: "off", 1: "running"},
    "safe_state": {0: "BCU commands applied", 1: "safe state"},
    # rb_wsp_mode (core/include/railbrake/rb_bcu.h)
    "wsp_mode": {-1: "no default WSP (off, or a user function)", 0: "apply", 1: "vent", 2: "hold", 3: "re-apply",
                 4: "inhibited: safety timer tripped on commanded venting",
                 5: "isolated: safety timer tripped on a cylinder vented without command"},
}
# wsp_mode values from which the axle's safety timer has tripped (kept to the end of the run)
WSP_TRIPPED = (4, 5)


# channels of numbers in named ranges: [lower, upper) -> text (MDF4 value-range-to-text; for floats
# the upper limit is excluded); the raw value stays in the file (asammdf's get(name, raw=True))
RANGES = {
    "brake_demand": [(0.0, 1e-9, "release"), (1e-9, 1.0 + 1e-6, "service (raw value: the fraction of full service)"),
                     (1.0 + 1e-6, 1e3, "emergency")],
}


def demand_text(value: float) -> str:
    """'release', 'service 40 %', 'emergency': a brake demand (the HIL frames' brake_demand: 0 .. 1
    of full service, > 1 emergency) as a driver reads it."""
    if value > 1.0:
        return "emergency"
    return "release" if value <= 0.0 else f"service {100.0 * value:.0f} %"


def base_name(channel: str) -> str:
    return re.sub(r"_c\d+(a\d+)?$", "", channel)


def comment(channel: str) -> str:
    match = re.search(r"_c(\d+)(?:a(\d+))?$", channel)
    where = "" if not match else f" (car {match.group(1)}" + (f", axle {match.group(2)})" if match.group(2) else ")")
    return COMMENTS.get(base_name(channel), channel) + where


def conversion(channel: str) -> dict | None:
    """asammdf's value-to-text conversion of an integer channel, a value-range-to-text one of a
    channel in RANGES, None for the others."""
    ranges = RANGES.get(base_name(channel))
    if ranges is not None:
        out = {"default_addr": "outside the named ranges"}
        for i, (low, high, text) in enumerate(ranges):
            out[f"lower_{i}"], out[f"upper_{i}"], out[f"text_{i}"] = low, high, text
        return out
    states = STATES.get(base_name(channel))
    if states is None:
        return None
    out = {}
    for i, (value, text) in enumerate(states.items()):
        out[f"val_{i}"], out[f"text_{i}"] = value, text
    return out
