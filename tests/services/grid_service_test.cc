// GridService with typed requests and results on a real SQLite file, without HTTP: the injected clock stamps
// maps, layers and agents, and observations, labels, regions, attention and viewpoints answer in typed form.
#include "services/grid/grid_service.h"

#include <gtest/gtest.h>

#include <memory>

#include "schema/error.h"
#include "storage/store.h"
#include "tests/support/grid_test_map.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace grid_service_test {

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;

Polygon2 Square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

class GridServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    storage::StoreOptions o;
    o.path = dir_.File("db.sqlite");
    store_ = std::make_unique<storage::Store>(o);
    grid_ = std::make_unique<GridService>(*store_, ServiceLimits{}, GridDefaults{}, clock_);
    grid_->CreateMap({"m", "test"});
    grid_->ImportOccupancyLayer({"m", "occ", testing::GridTestYaml(), testing::GridTestPgm()});
  }
  testing::TempDir dir_;
  FakeClock clock_{kStartNs};
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<GridService> grid_;
};

TEST_F(GridServiceTest, TheInjectedClockStampsMapsLayersAndAgents) {
  EXPECT_EQ(grid_->GetMap("m").map.created_ns, kStartNs);
  const LayerInfo occ = grid_->GetLayer("m", "occ", false);
  EXPECT_EQ(occ.created_ns, kStartNs);
  EXPECT_EQ(occ.updated_ns, kStartNs);

  clock_.AdvanceNs(5);
  grid_->CreateLayer({"m", "prob", ProbabilityLayerSpec{"occ", {}}});
  clock_.AdvanceNs(5);
  engine::Observation o;
  o.sensor_position_m = {0.5, 0.5};
  o.stimulus_map = {Square(0.9, 0.2, 1.2, 0.5)};
  grid_->Observe({"m", "prob", o});
  const LayerInfo prob = grid_->GetLayer("m", "prob", false);
  EXPECT_EQ(prob.created_ns, kStartNs + 5);
  EXPECT_EQ(prob.updated_ns, kStartNs + 10);

  Agent a;
  a.id = "p";
  EXPECT_EQ(grid_->PutAgent({"m", a, std::nullopt}).stamp_ns, kStartNs + 10);
  EXPECT_EQ(grid_->PutAgent({"m", a, 42}).stamp_ns, 42);
  EXPECT_EQ(grid_->GetAgent("m", "p").stamp_ns, 42);
}

TEST_F(GridServiceTest, ObservationsCountCellsAndBumpTheVersion) {
  grid_->CreateLayer({"m", "prob", ProbabilityLayerSpec{"occ", {}}});
  engine::Observation o;
  o.sensor_position_m = {0.5, 0.5};
  o.fov_rad = 1.0;
  o.range_m = 2.0;
  o.stimulus_map = {Square(0.9, 0.2, 1.2, 0.5)};
  const ObservationResult r = grid_->Observe({"m", "prob", o});
  EXPECT_EQ(r.layer, "prob");
  EXPECT_EQ(r.version, 2);
  EXPECT_GT(r.counts.raised, 0u);
  EXPECT_GT(r.counts.lowered, 0u);
  EXPECT_EQ(std::get<storage::ProbabilityLayerMeta>(grid_->GetLayer("m", "prob", false).meta).observations, 1);

  o.sensor_position_m = {50.0, 0.5};
  try {
    grid_->Observe({"m", "prob", o});
    FAIL() << "expected kUnprocessable";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "pose.position");
  }
  EXPECT_THROW(grid_->Observe({"m", "occ", o}), Error);
}

TEST_F(GridServiceTest, LabelsGetIdsAndBecomeRegionsAPersonAttendsTo) {
  grid_->CreateLayer({"m", "lab", LabelLayerSpec{"occ", {}}});
  const PaintLabelResult k = grid_->PaintLabel({"m", "lab", "kitchen", {Square(0.0, 0.0, 0.5, 0.5)}});
  EXPECT_EQ(k.label_id, 1);
  EXPECT_EQ(k.cells, 25u);
  EXPECT_EQ(grid_->PaintLabel({"m", "lab", "hall", {Square(1.5, 1.5, 1.8, 1.8)}}).label_id, 2);
  EXPECT_EQ(grid_->PaintLabel({"m", "lab", "kitchen", {Square(0.0, 0.0, 0.1, 0.1)}}).label_id, 1);

  const LayerRegions regions = grid_->Regions({"m", "lab", 0.5, 0.0});
  ASSERT_EQ(regions.regions.size(), 2u);
  EXPECT_EQ(regions.version, 4);
  EXPECT_EQ(regions.regions[0].cell_count, 25u);

  Agent a;
  a.id = "p";
  a.position_m = {-0.2, 0.25};  // just left of the kitchen, facing it
  grid_->PutAgent({"m", a, 1});
  const AttentionResult attention = grid_->Attention({"m", "p", "lab", 0.5});
  EXPECT_TRUE(attention.attention.attending);
  ASSERT_TRUE(attention.region.has_value());
  EXPECT_EQ(attention.region->id, 1);

  const ViewpointsResult plan = grid_->Viewpoints({"m", {1.0, 1.0}, "p", "lab", 0.5, std::nullopt, 3});
  EXPECT_EQ(plan.region.id, 1);
  EXPECT_FALSE(plan.plan.viewpoints.empty());
  EXPECT_LE(plan.plan.viewpoints.size(), 3u);
  try {
    grid_->Viewpoints({"m", {1.0, 1.0}, "p", "lab", 0.5, 7, 3});
    FAIL() << "expected kNotFound";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
    EXPECT_EQ(e.field(), "region");
  }
}

TEST_F(GridServiceTest, MapsPageByCursorAndLayersListInNameOrder) {
  grid_->CreateMap({"n", "second"});
  grid_->CreateMap({"o", "third"});
  const MapPage first = grid_->ListMaps({"", 2});
  ASSERT_EQ(first.maps.size(), 2u);
  ASSERT_TRUE(first.next_cursor.has_value());
  EXPECT_EQ(*first.next_cursor, "n");
  const MapPage rest = grid_->ListMaps({*first.next_cursor, 2});
  ASSERT_EQ(rest.maps.size(), 1u);
  EXPECT_EQ(rest.maps[0].id, "o");
  EXPECT_FALSE(rest.next_cursor.has_value());

  grid_->CreateLayer({"m", "a_prob", ProbabilityLayerSpec{"occ", {}}});
  const std::vector<LayerInfo> layers = grid_->ListLayers("m");
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_EQ(layers[0].name, "a_prob");
  EXPECT_EQ(grid_->GetMap("m").layers.size(), 2u);
  EXPECT_THROW(grid_->DeleteLayer("m", "occ"), Error);  // a_prob depends on it
}

}  // namespace
}  // namespace anchordb::services
