-- wrk script for scripts/bench-engines: every request POSTs an operator's label to the instance of the URL (a write
-- route: one transaction that updates the instance, adds its history row and a 'labelled' event), then reports as
-- wrk_report.lua does.
wrk.method = "POST"
wrk.body = '{"label":"keys","source":"operator"}'
wrk.headers["Content-Type"] = "application/json"
dofile("bench/wrk_report.lua")
