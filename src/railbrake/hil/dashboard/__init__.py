"""The live dashboard of a HIL run (`railbrake hil ... --dashboard [HOST:]PORT`, docs/hil.md):
a local web page showing the running loop (speeds, cylinders, WSP valves, slip, reservoirs,
demand, BCU frame health, overruns, the safe state), injecting and clearing faults and stopping
the run. The page polls the loop's live snapshot (live.LiveView: the loop never waits on the
network); every script and style ships here (static/), nothing is fetched from the internet.

127.0.0.1 by default. Every API call carries the run's token (`Authorization: Bearer TOKEN` or
`?token=TOKEN`), checked before any body is read; on another host the page itself is served only
with it too (the URL printed at the start holds it). No client can jam it (guard.Guard: connections
capped per peer and overall, the oldest one that never carried the token closed to make room, reads
time out, bodies and JSON nesting bounded): a malformed request gets an HTTP error (400, 401, 404,
411, 413), never a traceback."""


from railbrake.hil.dashboard.server import MAX_BODY, STATIC, Dashboard

__all__ = ["Dashboard", "MAX_BODY", "STATIC"]
