#include "tests/eval/events_eval.h"

#include <Eigen/Core>
#include <httplib.h>

#include <cstdio>

namespace anchordb::testing {

EventsSummary RunEventsEvaluation(int port, std::uint64_t first_seed, int count, bool verbose) {
  EventsSummary summary;
  for (int k = 0; k < count; ++k) {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(60, 0);
    sim::LostKeyOptions o;
    o.seed = first_seed + static_cast<std::uint64_t>(k);
    o.map = "run-" + std::to_string(o.seed);
    if (verbose) o.log = [](const std::string& line) { std::printf("    %s\n", line.c_str()); };
    const sim::LostKeyResult result = sim::RunLostKeyScenario(client, o);
    EventsRun run;
    run.seed = o.seed;
    run.score = sim::ScoreEvents(result);
    const sim::EventCounts t = run.score.Total();
    run.events_right = t.fp == 0 && t.fn == 0;
    run.sentence = result.where.value("sentence", result.where.dump());
    if (result.where.contains("position_m")) {
      const auto p = result.where["position_m"];
      const double error = (Eigen::Vector3d(p[0], p[1], p[2]) - result.keys_true_m).norm();
      run.where_right = result.where.value("present", false) && run.sentence.find("table") != std::string::npos && error <= 0.15;
    }
    if (result.past_where.contains("position_m")) {
      const auto p = result.past_where["position_m"];
      run.past_right = !result.past_where.value("present", true) &&
                       (Eigen::Vector3d(p[0], p[1], p[2]) - result.keys_before_m).norm() <= 0.15 &&
                       result.past_where.value("sentence", std::string()).find("shelf") != std::string::npos;
    }
    for (const auto& pair : {std::make_pair(&summary.total.observed, &run.score.observed), std::make_pair(&summary.total.meanwhile, &run.score.meanwhile)}) {
      pair.first->tp += pair.second->tp;
      pair.first->fp += pair.second->fp;
      pair.first->fn += pair.second->fn;
    }
    summary.runs.push_back(run);
  }
  return summary;
}

}  // namespace anchordb::testing
