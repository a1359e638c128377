#include "services/events/where_inputs_cache.h"

namespace anchordb::services {

bool WhereInputsCache::Holds(const std::string& map, const std::string& label) const {
  std::lock_guard lock(mutex_);
  return entries_.count({map, label}) != 0;
}

std::optional<storage::WhereInputs> WhereInputsCache::Find(const std::string& map, const std::string& label,
                                                           const storage::WhereStamp& stamp) const {
  std::lock_guard lock(mutex_);
  const auto it = entries_.find({map, label});
  if (it == entries_.end() || !(it->second.stamp == stamp)) return std::nullopt;
  ++hits_;
  return it->second;
}

void WhereInputsCache::Put(const std::string& map, const std::string& label, const storage::WhereInputs& inputs) {
  if (max_entries_ == 0 || !inputs.stamp.map_created_ns) return;
  std::lock_guard lock(mutex_);
  Key key{map, label};
  const auto it = entries_.find(key);
  if (it != entries_.end()) {
    it->second = inputs;
    return;
  }
  if (entries_.size() >= max_entries_) {
    entries_.erase(order_.front());
    order_.pop_front();
  }
  entries_.emplace(key, inputs);
  order_.push_back(std::move(key));
}

std::int64_t WhereInputsCache::hits() const {
  std::lock_guard lock(mutex_);
  return hits_;
}

std::size_t WhereInputsCache::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace anchordb::services
