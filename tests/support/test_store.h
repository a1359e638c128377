#pragma once
// A store for repository tests: the test database (a SQLite file or a scratch PostgreSQL database), one reader
// connection, and the given maps already there (each named as its id).
#include <initializer_list>
#include <memory>
#include <string>

#include "storage/repositories.h"
#include "storage/store.h"

namespace anchordb::testing {

inline std::unique_ptr<storage::Store> OpenStoreWithMaps(const std::string& location, std::initializer_list<std::string> maps) {
  storage::StoreOptions o;
  o.path = location;
  o.reader_connections = 1;
  auto store = std::make_unique<storage::Store>(o);
  store->Write([&](storage::Connection& c) {
    for (const std::string& id : maps) storage::InsertMap(c, {id, id, 1});
  });
  return store;
}

}  // namespace anchordb::testing
