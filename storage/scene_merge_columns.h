#pragma once
// Internal to storage/: the merge report's scalar columns of a scene_models row and its three child tables
// (migration 0022), read and written for scene_repository.cc.
#include "storage/connection.h"
#include "storage/scene_merge_report.h"

namespace anchordb::storage::merge_report {

// The scalar columns, in the order Read and Bind take them.
extern const char* const kColumns;
constexpr int kColumnCount = 16;

// Reads the scalar columns from column `first`; returns the number of child rows to load (ReadLists).
std::int64_t Read(const Statement& s, int first, MergeReportRecord& report);
// Binds the scalar columns to parameters first .. first + kColumnCount - 1.
void Bind(Statement& s, int first, const MergeReportRecord& report);

void ReadLists(Connection& c, std::int64_t scene_id, MergeReportRecord& report);
// Replaces the child rows of the scene with the lists of `report`.
void ReplaceLists(Connection& c, std::int64_t scene_id, const MergeReportRecord& report);

}  // namespace anchordb::storage::merge_report
