"""Results of a run as a brake engineer reads them: one record (time series, units, KPIs, what
was run and by whom), its exports (Parquet, CSV, MDF4), loading a saved run back, the HTML report
and comparing runs. The plots live in railbrake.plots.simulation."""

from railbrake.results.record import RunRecord, from_hil, from_simulation

__all__ = ["RunRecord", "from_hil", "from_simulation"]
