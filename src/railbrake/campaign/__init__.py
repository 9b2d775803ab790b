"""Campaigns: studies of many configurations (factors, designs, seeds) run on dask.distributed
into a resumable Parquet dataset, EN 15595-style WSP assessment, WSP tuning and reports.

study (files) -> plan (runs and keys) -> execute (Dask) -> dataset (Parquet) -> assess / report.
User guide: docs/campaigns.md.
"""
