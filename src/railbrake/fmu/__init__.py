"""The real-time plant as a co-simulation FMU (FMI 2.0 / 3.0) for HIL targets: docs/fmu.md."""

from railbrake.fmu.export import export_fmu

__all__ = ["export_fmu"]
