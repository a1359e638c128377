#pragma once
// The event-detection evaluation of thesis 3.5.2: the lost-key scenario (sim/lost_key_scenario.h) repeated with
// seeded variation against a real server on loopback, each run on a map of its own; expected vs detected events
// per run, split into observed and meanwhile changes, and whether "where are my keys?" names the right place.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/lost_key_scenario.h"

namespace anchordb::testing {

struct EventsRun {
  std::uint64_t seed = 0;
  sim::EventScore score;
  bool events_right = false;    // every expected event found, nothing else
  bool where_right = false;     // the answer names the table (place A) and lies within 15 cm of the keys
  bool past_right = false;      // at a time between taking and bringing, the keys were last seen at B
  std::string sentence;
};

struct EventsSummary {
  std::vector<EventsRun> runs;
  sim::EventScore total;
  static double Recall(const sim::EventCounts& c) { return c.tp + c.fn ? double(c.tp) / (c.tp + c.fn) : 1.0; }
  static double Precision(const sim::EventCounts& c) { return c.tp + c.fp ? double(c.tp) / (c.tp + c.fp) : 1.0; }
  // Error rate of a class as the thesis counts it: wrong decisions (FP + FN) over expected events.
  static double ErrorRate(const sim::EventCounts& c) { return c.tp + c.fn ? double(c.fp + c.fn) / (c.tp + c.fn) : 0.0; }
};

// Runs seeds first_seed .. first_seed + count - 1 against the server on 127.0.0.1:port.
EventsSummary RunEventsEvaluation(int port, std::uint64_t first_seed, int count, bool verbose);

}  // namespace anchordb::testing
