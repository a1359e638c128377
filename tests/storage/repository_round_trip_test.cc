// Round trips of the repositories of the later capabilities, on both engines (issue 35): jobs, shape models,
// instance classifications and perceived furniture. What is written reads back field for field (binary blobs byte
// for byte), an upsert replaces, filters and orders hold, and deleting a map takes its rows along.
#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/blob_codec.h"
#include "storage/event_repository.h"
#include "storage/furniture_instance_repository.h"
#include "storage/instance_classification_repository.h"
#include "storage/job_documents.h"
#include "storage/job_repository.h"
#include "storage/repositories.h"
#include "storage/shape_documents.h"
#include "storage/shape_repository.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"
#include "tests/support/test_store.h"

namespace anchordb::storage {
namespace repository_round_trip_test {

using namespace std::string_literals;

class RepositoryRoundTripTest : public ::testing::TestWithParam<Engine> {
 protected:
  void SetUp() override { store_ = testing::OpenStoreWithMaps(db_.location(), {"home", "other"}); }
  std::int64_t NewInstance(const std::string& map, const std::string& kind) {
    return store_->Write([&](Connection& c) {
      InstanceRecord r;
      r.map_id = map;
      r.kind = kind;
      r.created_ns = r.updated_ns = r.last_seen_ns = 5;
      return InsertInstance(c, r);
    });
  }
  std::optional<JobRecord> Job(std::int64_t id) {
    return store_->Read([&](Connection& c) { return FindJob(c, id); });
  }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Store> store_;
};

INSTANTIATE_TEST_SUITE_P(Engines, RepositoryRoundTripTest, testing::BothEngines(), testing::EngineName);

TEST_P(RepositoryRoundTripTest, JobsKeepTheirFieldsStatusesAndOrder) {
  const auto [backup, forget, segment] = store_->Write([](Connection& c) {
    // One statement each, in this order (the arguments of one call are evaluated in an unspecified order).
    const std::int64_t b = InsertJob(c, "backup", std::nullopt, EncodeBackupRequest({"/b/nightly.sqlite"}), 10, "0000000a");
    const std::int64_t f = InsertJob(c, "forget", "home"s, EncodeForgetRequest({}), 20, "0000000a");
    return std::make_tuple(b, f, InsertJob(c, "segment", "other"s, "any bytes\0\xff"s, 30, "0000000a"));
  });
  const JobRecord f = *Job(forget);
  EXPECT_EQ(f.kind, "forget");
  EXPECT_EQ(f.map_id, "home");
  EXPECT_EQ(f.status, JobStatus::kQueued);
  EXPECT_EQ(f.request.encoded, EncodeForgetRequest({}));
  EXPECT_TRUE(f.request.legacy_json.empty());
  EXPECT_EQ(f.progress, 0.0);
  EXPECT_EQ(f.created_ns, 20);
  EXPECT_EQ(f.updated_ns, 20);
  EXPECT_FALSE(f.result.has_value());
  EXPECT_FALSE(f.error.has_value());
  EXPECT_FALSE(Job(backup)->map_id.has_value());
  EXPECT_EQ(DecodeBackupRequest(Job(backup)->request.encoded, "job").file, "/b/nightly.sqlite");
  EXPECT_EQ(Job(segment)->request.encoded, "any bytes\0\xff"s);  // a kind's document is bytes, kept exactly
  EXPECT_FALSE(Job(segment + 1000).has_value());
  // The oldest queued first, and after a given id.
  EXPECT_EQ(store_->Read([](Connection& c) { return NextQueuedJob(c, "0000000a"); }), backup);
  EXPECT_EQ(store_->Read([&, b = backup](Connection& c) { return NextQueuedJob(c, "0000000a", b); }), forget);
  EXPECT_FALSE(store_->Read([](Connection& c) { return NextQueuedJob(c, "0000000b"); })) << "another server's queue";
  // Status changes: a result stays when none is given; an error is replaced, and cleared by none.
  const std::string result = EncodeBackupReport({"/b/nightly.sqlite", 123, 1, 0, "ok", 0.5}), error = "disk full";
  store_->Write([&, b = backup, fo = forget](Connection& c) {
    SetJobStatus(c, b, JobStatus::kRunning, "copying", 0.5, nullptr, nullptr, 40);
    SetJobStatus(c, fo, JobStatus::kFailed, "deleting", 0.25, nullptr, &error, 41);
  });
  EXPECT_EQ(Job(backup)->status, JobStatus::kRunning);
  EXPECT_EQ(Job(backup)->stage, "copying");
  EXPECT_EQ(Job(backup)->progress, 0.5);
  EXPECT_EQ(Job(backup)->updated_ns, 40);
  EXPECT_EQ(Job(forget)->error, error);
  store_->Write([&, b = backup, fo = forget](Connection& c) {
    SetJobStatus(c, b, JobStatus::kSucceeded, "done", 1.0, &result, nullptr, 50);
    SetJobStatus(c, b, JobStatus::kSucceeded, "done", 1.0, nullptr, nullptr, 51);
    SetJobStatus(c, fo, JobStatus::kFailed, "deleting", 0.25, nullptr, nullptr, 52);
  });
  ASSERT_TRUE(Job(backup)->result.has_value());
  EXPECT_EQ(Job(backup)->result->encoded, result);
  EXPECT_EQ(DecodeBackupReport(Job(backup)->result->encoded, "job").bytes, 123);
  EXPECT_EQ(Job(backup)->status, JobStatus::kSucceeded);
  EXPECT_FALSE(Job(forget)->error.has_value());
  EXPECT_EQ(store_->Read([](Connection& c) { return NextQueuedJob(c, "0000000a"); }), segment);
  // Newest first, by map, before an id, at most a limit.
  const auto ids = [&](const std::optional<std::string>& map, std::int64_t before, int limit) {
    std::vector<std::int64_t> out;
    for (const auto& j : store_->Read([&](Connection& c) { return ListJobs(c, map, before, limit); })) out.push_back(j.id);
    return out;
  };
  EXPECT_EQ(ids(std::nullopt, 0, 10), (std::vector<std::int64_t>{segment, forget, backup}));
  EXPECT_EQ(ids("home"s, 0, 10), std::vector<std::int64_t>{forget});
  EXPECT_EQ(ids(std::nullopt, segment, 10), (std::vector<std::int64_t>{forget, backup}));
  EXPECT_EQ(ids(std::nullopt, 0, 1), std::vector<std::int64_t>{segment});
  // A stop leaves the queued and running jobs failed; one that had recorded its result gets its kind's note.
  const std::int64_t running = store_->Write([&](Connection& c) {
    const std::int64_t id = InsertJob(c, "backup", std::nullopt, EncodeBackupRequest({"/b/x.sqlite"}), 60, "0000000a");
    SetJobStatus(c, id, JobStatus::kRunning, "writing", 0.9, &result, nullptr, 61);
    return id;
  });
  // Another server's queued job, and one written before jobs had a server (migration 0030).
  const auto [other, nobodys] = store_->Write([](Connection& c) {
    const std::int64_t o = InsertJob(c, "segment", "home"s, "{}", 62, "0000000b");
    const std::int64_t n = InsertJob(c, "segment", "home"s, "{}", 63, "0000000b");
    Statement(c, "UPDATE jobs SET server_id = NULL WHERE id = ?").Bind(1, n).Run();
    return std::make_pair(o, n);
  });
  EXPECT_EQ(store_->Read([](Connection& c) { return UnfinishedJobServers(c); }),
            (std::vector<std::optional<std::string>>{std::nullopt, "0000000a"s, "0000000b"s}));
  const int failed = store_->Write([](Connection& c) {
    return MarkUnfinishedJobsFailed(c, "0000000a"s, "the server stopped", 70, {{"backup", "the copy was written"}});
  });
  EXPECT_EQ(failed, 2);
  EXPECT_EQ(Job(other)->status, JobStatus::kQueued) << "another server's job is not this server's to fail";
  EXPECT_EQ(Job(nobodys)->status, JobStatus::kQueued);
  EXPECT_EQ(store_->Write([](Connection& c) { return MarkUnfinishedJobsFailed(c, std::nullopt, "gone", 71); }), 1);
  EXPECT_EQ(Job(nobodys)->status, JobStatus::kFailed);
  EXPECT_EQ(Job(other)->status, JobStatus::kQueued);
  for (const std::int64_t id : {segment, running}) {
    EXPECT_EQ(Job(id)->status, JobStatus::kFailed);
    EXPECT_NE(Job(id)->error.value_or("").find("the server stopped"), std::string::npos) << id;
  }
  EXPECT_NE(Job(running)->error->find("the copy was written"), std::string::npos);
  EXPECT_EQ(Job(segment)->error->find("the copy was written"), std::string::npos);
  EXPECT_EQ(Job(backup)->status, JobStatus::kSucceeded);  // finished jobs are left alone
  // Deleting a map takes its jobs; a job of no map stays.
  store_->Write([](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_FALSE(Job(forget).has_value());
  EXPECT_TRUE(Job(backup).has_value());
}

TEST_P(RepositoryRoundTripTest, ShapeModelsRoundTripReplaceListAndDelete) {
  ShapeModelRecord r;
  r.name = "chairs";
  r.created_ns = 10;
  r.model = "ISM\0\x01\xff model bytes"s;  // binary, with NUL and high bytes
  ShapeModelOptionsRecord options;
  options.name = "chairs";
  options.params.codebook_size = 60;
  options.params.seed = 7;
  options.mesh_views = 12;
  options.parts = {{"chair.obj", "chair", true, 812}, {"scan.pcd", "chair", false, 4000}};
  r.options.encoded = EncodeShapeModelOptions(options);
  ShapeModelReportRecord report;
  report.categories = {{"chair", 13, 480}};
  report.samples = 13;
  report.train_seconds = 1.5;
  r.report.encoded = EncodeShapeModelReport(report);
  ShapeModelRecord tables = r;
  tables.name = "tables";
  store_->Write([&](Connection& c) {
    UpsertShapeModel(c, r);
    UpsertShapeModel(c, tables);
  });
  const auto got = store_->Read([](Connection& c) { return GetShapeModel(c, "chairs", true); });
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->model, r.model);
  EXPECT_EQ(got->created_ns, 10);
  EXPECT_EQ(got->options.encoded, r.options.encoded);
  EXPECT_EQ(got->report.encoded, r.report.encoded);
  EXPECT_TRUE(got->options.legacy_json.empty());
  const ShapeModelOptionsRecord options_back = DecodeShapeModelOptions(got->options.encoded, "options");
  EXPECT_EQ(options_back.params.codebook_size, 60);
  EXPECT_EQ(options_back.params.seed, 7u);
  ASSERT_EQ(options_back.parts.size(), 2u);
  EXPECT_TRUE(options_back.parts[0].mesh);
  EXPECT_EQ(options_back.parts[1].count, 4000);
  EXPECT_EQ(DecodeShapeModelReport(got->report.encoded, "report").categories.at(0).keypoints, 480);
  EXPECT_TRUE(store_->Read([](Connection& c) { return GetShapeModel(c, "chairs", false); })->model.empty());
  const auto listed = store_->Read([](Connection& c) { return ListShapeModels(c); });
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].name, "chairs");
  EXPECT_EQ(listed[1].name, "tables");
  EXPECT_TRUE(listed[0].model.empty());
  r.created_ns = 20;
  r.model = "retrained"s;
  store_->Write([&](Connection& c) { UpsertShapeModel(c, r); });
  EXPECT_EQ(store_->Read([](Connection& c) { return GetShapeModel(c, "chairs", true); })->model, "retrained");
  EXPECT_EQ(store_->Read([](Connection& c) { return ListShapeModels(c); }).size(), 2u);
  EXPECT_TRUE(store_->Write([](Connection& c) { return DeleteShapeModel(c, "chairs"); }));
  EXPECT_FALSE(store_->Write([](Connection& c) { return DeleteShapeModel(c, "chairs"); }));
  EXPECT_FALSE(store_->Read([](Connection& c) { return GetShapeModel(c, "chairs", true); }).has_value());
  // A row written before migration 0027 (JSON text, no documents) reads as its text, for the API to show as it was.
  store_->Write([](Connection& c) {
    Statement s(c, "INSERT INTO shape_models (name, created_ns, model, request_json, report_json) VALUES ('old', 1, ?, ?, ?)");
    s.BindBlob(1, EncodeBlob(BlobElement::kU8, {3}, "ISM")).Bind(2, R"({"name":"old"})").Bind(3, R"({"samples":4})").Run();
  });
  const auto old = store_->Read([](Connection& c) { return GetShapeModel(c, "old", true); });
  ASSERT_TRUE(old.has_value());
  EXPECT_EQ(old->model, "ISM");
  EXPECT_TRUE(old->options.encoded.empty());
  EXPECT_EQ(old->options.legacy_json, R"({"name":"old"})");
  EXPECT_EQ(old->report.legacy_json, R"({"samples":4})");
  EXPECT_EQ(store_->Read([](Connection& c) { return ListShapeModels(c); }).at(0).report.legacy_json, R"({"samples":4})");
}

TEST_P(RepositoryRoundTripTest, InstanceClassificationsAreOnePerInstanceOfItsMap) {
  const std::int64_t cup = NewInstance("home", "object");
  InstanceClassificationRecord r;
  r.instance_id = cup;
  r.map_id = "home";
  r.classifier = "kitchen";
  r.label = "cup";
  r.distribution = {{"cup", 0.7}, {"mug", 0.3}};
  r.stamp_ns = 10;
  store_->Write([&](Connection& c) { UpsertInstanceClassification(c, r); });
  const auto got = store_->Read([&](Connection& c) { return FindInstanceClassification(c, "home", cup); });
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->classifier, "kitchen");
  EXPECT_EQ(got->label, "cup");
  EXPECT_EQ(got->distribution, r.distribution);
  EXPECT_EQ(got->stamp_ns, 10);
  EXPECT_FALSE(got->segment_id.has_value());
  EXPECT_FALSE(got->keyframe_id.has_value());
  EXPECT_FALSE(store_->Read([&](Connection& c) { return FindInstanceClassification(c, "other", cup); }).has_value());
  EXPECT_FALSE(store_->Read([&](Connection& c) { return FindInstanceClassification(c, "home", cup + 1); }).has_value());
  r.label = "mug";
  r.distribution = {{"mug", 0.8}, {"spoon", 0.2}};  // a class gone, one new: the rows are replaced
  r.stamp_ns = 20;
  store_->Write([&](Connection& c) { UpsertInstanceClassification(c, r); });
  const auto replaced = store_->Read([&](Connection& c) { return FindInstanceClassification(c, "home", cup); });
  EXPECT_EQ(replaced->label, "mug");
  EXPECT_EQ(replaced->distribution, r.distribution);
  const auto rows = store_->Read([](Connection& c) {
    Statement s(c, "SELECT COUNT(*) FROM instance_classifications");
    s.Step();
    return s.Int(0);
  });
  EXPECT_EQ(rows, 1);
  // A classification must name an instance that exists (a foreign key): refused, and nothing stays.
  InstanceClassificationRecord stray = r;
  stray.instance_id = cup + 1000;
  EXPECT_THROW(store_->Write([&](Connection& c) { UpsertInstanceClassification(c, stray); }), Error);
  store_->Write([](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_FALSE(store_->Read([&](Connection& c) { return FindInstanceClassification(c, "home", cup); }).has_value());
}

TEST_P(RepositoryRoundTripTest, PerceivedFurnitureRoundTripsWithItsCloud) {
  const std::int64_t table = NewInstance("home", "furniture"), shelf = NewInstance("home", "furniture");
  const std::int64_t job = store_->Write([](Connection& c) { return InsertJob(c, "segment", "home"s, "{}", 1, "0000000a"); });
  FurnitureInstanceRecord r;
  r.instance_id = table;
  r.map_id = "home";
  r.classifier = "geometry";
  r.min_z_m = 0.02;
  r.height_m = 0.74;
  r.observations = 2;
  r.evidence_keyframes = {3, 4};
  r.cloud = "\0\0\x80?\x01\x02\x03\xff"s;  // binary
  r.created_ns = 10;
  r.updated_ns = 20;
  FurnitureInstanceRecord other = r;
  other.instance_id = shelf;
  other.job_id = job;
  other.cloud.clear();
  other.evidence_keyframes = {7};
  store_->Write([&](Connection& c) {
    UpsertFurnitureInstance(c, r);
    UpsertFurnitureInstance(c, other);
  });
  const auto got = store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "home", table, true); });
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->classifier, "geometry");
  EXPECT_EQ(got->min_z_m, 0.02);
  EXPECT_EQ(got->height_m, 0.74);
  EXPECT_EQ(got->observations, 2);
  EXPECT_EQ(got->evidence_keyframes, (std::vector<std::int64_t>{3, 4}));
  EXPECT_FALSE(got->job_id.has_value());
  EXPECT_EQ(got->cloud, r.cloud);
  EXPECT_EQ(got->created_ns, 10);
  EXPECT_EQ(got->updated_ns, 20);
  EXPECT_TRUE(store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "home", table, false); })->cloud.empty());
  EXPECT_EQ(store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "home", shelf, false); })->job_id, job);
  EXPECT_FALSE(store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "other", table, false); }).has_value());
  const auto listed = store_->Read([](Connection& c) { return ListFurnitureInstances(c, "home", false); });
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].evidence_keyframes, (std::vector<std::int64_t>{3, 4}));  // each piece its own
  EXPECT_EQ(listed[1].evidence_keyframes, std::vector<std::int64_t>{7});
  EXPECT_TRUE(store_->Read([](Connection& c) { return ListFurnitureInstances(c, "other", false); }).empty());
  r.observations = 3;
  r.evidence_keyframes = {3, 4, 9};
  r.updated_ns = 30;
  store_->Write([&](Connection& c) { UpsertFurnitureInstance(c, r); });
  const auto again = store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "home", table, true); });
  EXPECT_EQ(again->observations, 3);
  EXPECT_EQ(again->evidence_keyframes, (std::vector<std::int64_t>{3, 4, 9}));
  r.evidence_keyframes = {9};  // replaced, not joined: the service joins
  store_->Write([&](Connection& c) { UpsertFurnitureInstance(c, r); });
  EXPECT_EQ(store_->Read([&](Connection& c) { return FindFurnitureInstance(c, "home", table, false); })->evidence_keyframes,
            std::vector<std::int64_t>{9});
  EXPECT_EQ(again->updated_ns, 30);
  EXPECT_EQ(store_->Read([](Connection& c) { return ListFurnitureInstances(c, "home", true); }).size(), 2u);
  store_->Write([](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_TRUE(store_->Read([](Connection& c) { return ListFurnitureInstances(c, "home", false); }).empty());
}

}  // namespace
}  // namespace anchordb::storage
