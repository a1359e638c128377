-- wrk reporter for scripts/bench: after the run, prints one line "WRK_JSON {...}" with the exact counts and the
-- latency percentiles in microseconds (wrk's own text rounds them), which the script turns into http.json.
-- Note: wrk's latency histogram holds only requests that got a response; requests that never got one (for example
-- on a connection the server never serves) are not in it, so scripts/bench also counts served connections.
done = function(summary, latency, requests)
  local e = summary.errors
  io.write(string.format(
    'WRK_JSON {"requests":%d,"duration_us":%d,"bytes":%d,' ..
    '"errors":{"connect":%d,"read":%d,"write":%d,"status":%d,"timeout":%d},' ..
    '"latency_us":{"mean":%.1f,"stdev":%.1f,"max":%d,"p50":%d,"p90":%d,"p99":%d,"p999":%d}}\n',
    summary.requests, summary.duration, summary.bytes,
    e.connect, e.read, e.write, e.status, e.timeout,
    latency.mean, latency.stdev, latency.max,
    latency:percentile(50), latency:percentile(90), latency:percentile(99), latency:percentile(99.9)))
end
