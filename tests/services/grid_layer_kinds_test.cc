// The layer-kind table of the grid service (services/grid/layer_kinds.h): one entry per kind, every kind created
// from its spec reads back as it was made (metadata, probabilities, statistics, every export format), and a kind
// without an entry is a clear error.
#include "services/grid/layer_kinds.h"

#include <gtest/gtest.h>

#include <memory>
#include <set>

#include "schema/error.h"
#include "services/grid/grid_service.h"
#include "storage/store.h"
#include "tests/support/grid_test_map.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace grid_layer_kinds_test {

using grid_detail::KindOps;
using grid_detail::LayerKindOps;

constexpr LayerKind kEveryKind[] = {LayerKind::kOccupancy, LayerKind::kProbability, LayerKind::kFused, LayerKind::kLabel};

TEST(GridLayerKinds, EveryKindHasOneCompleteEntry) {
  std::set<LayerKind> seen;
  for (const LayerKindOps* ops : grid_detail::AllKinds()) EXPECT_TRUE(seen.insert(ops->kind).second);
  EXPECT_EQ(seen.size(), std::size(kEveryKind));
  for (LayerKind kind : kEveryKind) {
    const LayerKindOps& ops = KindOps(kind);
    EXPECT_EQ(ops.kind, kind);
    EXPECT_TRUE(ops.meta && ops.probability && ops.statistics && ops.export_own && ops.occupancy_base)
        << LayerKindName(kind);
    EXPECT_EQ(ops.create == nullptr, kind == LayerKind::kOccupancy) << LayerKindName(kind);
  }
}

TEST(GridLayerKinds, EverySpecNamesAKindThatCreatesFromIt) {
  for (const LayerSpec& spec : {LayerSpec{ProbabilityLayerSpec{}}, LayerSpec{FusedLayerSpec{}}, LayerSpec{LabelLayerSpec{}}}) {
    EXPECT_NE(KindOps(grid_detail::KindOf(spec)).create, nullptr);
  }
}

TEST(GridLayerKinds, AKindWithoutAnEntryIsAnInternalError) {
  try {
    KindOps(static_cast<LayerKind>(99));
    FAIL() << "expected kInternal";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    EXPECT_NE(std::string(e.what()).find("no entry in the kind table"), std::string::npos) << e.what();
  }
}

class GridLayerKindsRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    storage::StoreOptions o;
    o.path = dir_.File("db.sqlite");
    store_ = std::make_unique<storage::Store>(o);
    grid_ = std::make_unique<GridService>(*store_, ServiceLimits{}, GridDefaults{});
    grid_->CreateMap({"m", "test"});
    grid_->ImportOccupancyLayer({"m", "occ", testing::GridTestYaml(), testing::GridTestPgm()});
    grid_->CreateLayer({"m", "prob", ProbabilityLayerSpec{"occ", {0.8, 0.3, 0.1, 0.99}}});
    grid_->CreateLayer({"m", "lab", LabelLayerSpec{"occ", {{3, "hall"}}}});
    grid_->CreateLayer({"m", "fz", FusedLayerSpec{FuseOp::kOr, {{"occ", 0.6}, {"lab", 0.5}}}});
  }
  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<GridService> grid_;
};

TEST_F(GridLayerKindsRoundTrip, EveryKindReadsBackAsItWasMade) {
  const LayerInfo occ = grid_->GetLayer("m", "occ", true);
  const auto& occ_meta = std::get<storage::OccupancyLayerMeta>(occ.meta);
  EXPECT_EQ(occ_meta.geometry.width_cells, 40);
  EXPECT_EQ(occ_meta.map_server.image, "map.pgm");
  EXPECT_EQ(std::get<engine::OccupancyStatistics>(*occ.statistics).occupied_cells, 15u);

  const LayerInfo prob = grid_->GetLayer("m", "prob", true);
  const auto& prob_meta = std::get<storage::ProbabilityLayerMeta>(prob.meta);
  EXPECT_EQ(prob_meta.base, "occ");
  EXPECT_EQ(prob_meta.log_odds.hit_probability, 0.8);
  EXPECT_EQ(prob_meta.observations, 0);
  EXPECT_EQ(prob_meta.geometry, occ_meta.geometry);
  EXPECT_EQ(std::get<engine::ProbabilityStatistics>(*prob.statistics).mean_probability, 0.5);

  const LayerInfo lab = grid_->GetLayer("m", "lab", true);
  EXPECT_EQ(std::get<storage::LabelLayerMeta>(lab.meta).labels, (std::map<int, std::string>{{3, "hall"}}));
  EXPECT_TRUE(std::get<engine::LabelStatistics>(*lab.statistics).cells_per_label.empty());

  const LayerInfo fz = grid_->GetLayer("m", "fz", true);
  const auto& fz_meta = std::get<storage::FusedLayerMeta>(fz.meta);
  EXPECT_EQ(fz_meta.op, FuseOp::kOr);
  ASSERT_EQ(fz_meta.operands.size(), 2u);
  EXPECT_EQ(fz_meta.operands[0].threshold, 0.6);
  // The wall (occupancy 100 > 0.6) is the only true cell of the fused layer.
  EXPECT_EQ(std::get<engine::ProbabilityStatistics>(*fz.statistics).cells_above_half, 15u);
}

TEST_F(GridLayerKindsRoundTrip, EveryKindReadsAsProbabilitiesAndExportsEveryFormat) {
  store_->Read([&](storage::Connection& c) {
    const grid_detail::MapLayers layers(c, "m");
    for (const char* name : {"occ", "prob", "lab", "fz"}) {
      const storage::LayerRecord record = layers.Require(name);
      const engine::ProbabilityGrid p = layers.Probability(record);
      EXPECT_EQ(p.geometry, storage::DecodeGeometry(record)) << name;
      EXPECT_EQ(layers.OccupancyBase(record), "occ") << name;
    }
    return 0;
  });
  for (const char* name : {"occ", "prob", "lab", "fz"}) {
    for (LayerFormat f : {LayerFormat::kPng, LayerFormat::kPgm, LayerFormat::kYaml, LayerFormat::kRaw}) {
      const ExportedLayer e = grid_->ExportLayer("m", name, f);
      EXPECT_FALSE(e.body.empty()) << name;
      EXPECT_EQ(e.grid_width_cells, 40) << name;
      EXPECT_EQ(e.element != RawElement::kNone, f == LayerFormat::kRaw) << name;
      EXPECT_EQ(e.format == BytesFormat::kRaw, f == LayerFormat::kRaw) << name;
    }
  }
  EXPECT_EQ(grid_->ExportLayer("m", "prob", LayerFormat::kRaw).body.size(), 40u * 30u * sizeof(float));
  EXPECT_EQ(grid_->ExportLayer("m", "lab", LayerFormat::kRaw).body.size(), 40u * 30u * sizeof(std::uint16_t));
  EXPECT_EQ(grid_->ExportLayer("m", "fz", LayerFormat::kRaw).body.size(), 40u * 30u);
}

TEST_F(GridLayerKindsRoundTrip, ALayerOverANonOccupancyBaseIsRefused) {
  try {
    grid_->CreateLayer({"m", "p2", ProbabilityLayerSpec{"prob", {}}});
    FAIL() << "expected kUnprocessable";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnprocessable);
    EXPECT_EQ(e.field(), "base");
  }
}

}  // namespace
}  // namespace anchordb::services
