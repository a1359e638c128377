#pragma once
// The stored inputs of recent where-is answers for now (storage::ReadWhereInputs), per map and label, each with the
// map's stamp it was read at. A later question for now first reads the map's stamp (one statement of three index
// lookups) and reuses the inputs while it is equal: only a change of the map's instances, their labels or history,
// or a new furniture graph, makes the question read its inputs again. Frames, keyframes, layers and the OctoMap do
// not change the stamp, so a robot asking while it streams frames is answered from here until an analysis changes
// an object. Correct across servers on one database: the stamp is read from the database on every question, never
// assumed. Thread-safe; bounded (the oldest entry goes first); 0 entries: nothing is kept.
#include <cstddef>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "storage/event_repository.h"

namespace anchordb::services {

class WhereInputsCache {
 public:
  explicit WhereInputsCache(std::size_t max_entries) : max_entries_(max_entries) {}

  // True when inputs for this map and label are kept (whatever their stamp): only then is a stamp worth reading.
  bool Holds(const std::string& map, const std::string& label) const;
  // The inputs kept for this map and label when they were read at `stamp`; otherwise nothing.
  std::optional<storage::WhereInputs> Find(const std::string& map, const std::string& label,
                                           const storage::WhereStamp& stamp) const;
  // Keeps `inputs` (read at inputs.stamp) in place of any older ones; an absent map is not kept.
  void Put(const std::string& map, const std::string& label, const storage::WhereInputs& inputs);
  std::size_t size() const;
  std::int64_t hits() const;  // questions answered from kept inputs since start

 private:
  using Key = std::pair<std::string, std::string>;  // map, label
  std::size_t max_entries_;
  mutable std::mutex mutex_;
  std::map<Key, storage::WhereInputs> entries_;
  std::list<Key> order_;  // oldest first
  mutable std::int64_t hits_ = 0;
};

}  // namespace anchordb::services
