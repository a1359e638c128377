// The layers table on both engines (storage/layer_repository.cc, migration 0019): each kind's typed metadata and its
// lists round-trip, a layer with list rows is not complete from its row alone, an update replaces the lists, a
// deleted layer leaves no child rows, a row missing a value of its kind is kInternal, and the JSON documents of
// schema 18 read back through the typed columns.
#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/connection.h"
#include "storage/layer_codec.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace layer_repository_test {

class LayerRepositoryTest : public ::testing::TestWithParam<Engine> {
 protected:
  void SetUp() override {
    c_ = OpenConnection(db_.location(), ConnectionOptions{});
    ApplyMigrations(*c_, EmbeddedMigrations(GetParam()));
    InsertMap(*c_, {"home", "Home", 1});
  }
  std::int64_t Count(const std::string& table) {
    Statement s(*c_, "SELECT count(*) FROM " + table);
    s.Step();
    return s.Int(0);
  }
  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Connection> c_;
};
INSTANTIATE_TEST_SUITE_P(Engines, LayerRepositoryTest, testing::BothEngines(), testing::EngineName);

GridGeometry Geometry() {
  GridGeometry g;
  g.width_cells = 3;
  g.height_cells = 2;
  g.resolution_m = 0.025;
  g.origin_x_m = -1.25;
  g.origin_y_m = 2.5;
  g.origin_yaw_rad = 0.125;
  return g;
}

LayerRecord Record(const std::string& name) {
  LayerRecord r;
  r.map_id = "home";
  r.name = name;
  r.created_ns = r.updated_ns = 7;
  return r;
}

OccupancyLayer Occupancy(std::vector<std::string> ignored_keys) {
  OccupancyLayer layer;
  layer.meta.geometry = Geometry();
  layer.meta.map_server = {"floor.pgm", 0.025, {-1.25, 2.5, 0.125}, 1, 0.7, 0.2, MapMode::kScale, true};
  layer.meta.ignored_yaml_keys = std::move(ignored_keys);
  layer.image_pixels = {0, 254, 205, 1, 2, 3};
  return layer;
}

TEST_P(LayerRepositoryTest, EveryKindRoundTripsWithItsLists) {
  LayerRecord occ = Record("occ");
  EncodeLayer(Occupancy({"comment", "source"}), occ);
  InsertLayer(*c_, occ, {});
  LayerRecord plain = Record("plain");
  EncodeLayer(Occupancy({}), plain);
  InsertLayer(*c_, plain, {});
  LayerRecord prob = Record("prob");
  EncodeLayer(ProbabilityLayer{{Geometry(), "occ", {0.8, 0.3, 0.1, 0.99}, 12}, std::vector<float>(6, 0.5f)}, prob);
  InsertLayer(*c_, prob, {"occ"});
  LayerRecord fused = Record("fused");
  EncodeLayer(FusedLayerMeta{Geometry(), FuseOp::kAndNot, {{"prob", 0.25}, {"occ", 0.75}}}, fused);
  InsertLayer(*c_, fused, {"prob", "occ"});
  LayerRecord labels = Record("rooms");
  EncodeLayer(LabelLayer{{Geometry(), "occ", {{1, "hall"}, {300, "kitchen"}}}, std::vector<std::uint16_t>(6, 1)}, labels);
  InsertLayer(*c_, labels, {"occ"});

  const OccupancyLayer o = DecodeOccupancyLayer(*FindLayer(*c_, "home", "occ", true));
  EXPECT_EQ(o.meta.geometry, Geometry());
  EXPECT_EQ(o.meta.map_server.image, "floor.pgm");
  EXPECT_EQ(o.meta.map_server.origin[2], 0.125);
  EXPECT_EQ(o.meta.map_server.negate, 1);
  EXPECT_EQ(o.meta.map_server.occupied_thresh, 0.7);
  EXPECT_EQ(o.meta.map_server.mode, MapMode::kScale);
  EXPECT_TRUE(o.meta.map_server.mode_given);
  EXPECT_EQ(o.meta.ignored_yaml_keys, (std::vector<std::string>{"comment", "source"}));
  EXPECT_EQ(o.image_pixels, Occupancy({}).image_pixels);
  const ProbabilityLayer p = DecodeProbabilityLayer(*FindLayer(*c_, "home", "prob", true));
  EXPECT_EQ(p.meta.base, "occ");
  EXPECT_EQ(p.meta.log_odds.miss_probability, 0.3);
  EXPECT_EQ(p.meta.log_odds.clamp_max_probability, 0.99);
  EXPECT_EQ(p.meta.observations, 12);
  const FusedLayerMeta f = DecodeFusedMeta(*FindLayer(*c_, "home", "fused", false));
  EXPECT_EQ(f.op, FuseOp::kAndNot);
  ASSERT_EQ(f.operands.size(), 2u);
  EXPECT_EQ(f.operands[0].layer, "prob");
  EXPECT_EQ(f.operands[1].threshold, 0.75);
  const LabelLayerMeta l = DecodeLabelMeta(*FindLayer(*c_, "home", "rooms", false));
  EXPECT_EQ(l.labels, (std::map<int, std::string>{{1, "hall"}, {300, "kitchen"}}));

  // From the row alone: complete only without list rows.
  EXPECT_FALSE(FindLayerRow(*c_, "home", "occ")->complete);
  EXPECT_TRUE(FindLayerRow(*c_, "home", "plain")->complete);
  EXPECT_TRUE(FindLayerRow(*c_, "home", "prob")->complete);
  EXPECT_FALSE(FindLayerRow(*c_, "home", "fused")->complete);
  EXPECT_FALSE(FindLayerRow(*c_, "home", "rooms")->complete);
  EXPECT_FALSE(FindLayerRow(*c_, "home", "nothing").has_value());

  const std::vector<LayerRecord> all = ListLayers(*c_, "home");
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[0].name, "fused");
  EXPECT_EQ(DecodeFusedMeta(all[0]).operands.size(), 2u);
  EXPECT_EQ(DecodeOccupancyMeta(all[1]).ignored_yaml_keys.size(), 2u);
  EXPECT_EQ(DecodeLabelMeta(all[4]).labels.at(300), "kitchen");
}

TEST_P(LayerRepositoryTest, AnUpdateReplacesTheListsAndADeleteRemovesThem) {
  LayerRecord occ = Record("occ");
  EncodeLayer(Occupancy({}), occ);
  InsertLayer(*c_, occ, {});
  LayerRecord labels = Record("rooms");
  EncodeLayer(LabelLayer{{Geometry(), "occ", {{1, "hall"}, {2, "bath"}}}, std::vector<std::uint16_t>(6, 1)}, labels);
  InsertLayer(*c_, labels, {"occ"});

  LayerRecord changed = *FindLayer(*c_, "home", "rooms", true);
  LabelLayer layer = DecodeLabelLayer(changed);
  layer.meta.labels = {{2, "bathroom"}, {9, "study"}};
  EncodeLayer(layer, changed);
  changed.version = 2;
  UpdateLayer(*c_, changed, 1);
  EXPECT_EQ(DecodeLabelMeta(*FindLayer(*c_, "home", "rooms", false)).labels,
            (std::map<int, std::string>{{2, "bathroom"}, {9, "study"}}));
  EXPECT_EQ(Count("layer_label_names"), 2);

  LayerRecord other_kind = changed;
  EncodeLayer(ProbabilityLayer{{Geometry(), "occ", {}, 0}, std::vector<float>(6, 0.f)}, other_kind);
  other_kind.version = 3;
  EXPECT_THROW(UpdateLayer(*c_, other_kind, 2), Error);  // a stored layer keeps its kind

  EXPECT_TRUE(DeleteLayer(*c_, "home", "rooms"));
  EXPECT_EQ(Count("layer_label_names"), 0);
}

TEST_P(LayerRepositoryTest, ARowMissingAValueOfItsKindIsAnInternalErrorNamingTheLayer) {
  LayerRecord occ = Record("occ");
  EncodeLayer(Occupancy({}), occ);
  InsertLayer(*c_, occ, {});
  LayerRecord prob = Record("prob");
  EncodeLayer(ProbabilityLayer{{Geometry(), "occ", {}, 0}, std::vector<float>(6, 0.f)}, prob);
  InsertLayer(*c_, prob, {"occ"});
  c_->Exec("UPDATE layers SET hit_probability = NULL WHERE name = 'prob'");
  try {
    FindLayer(*c_, "home", "prob", false);
    ADD_FAILURE() << "a probability layer without its hit probability was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    EXPECT_NE(std::string(e.what()).find("'prob'"), std::string::npos) << e.what();
  }
}

std::vector<Migration> UpTo(Engine engine, int version) {
  std::vector<Migration> out;
  for (const Migration& m : EmbeddedMigrations(engine)) {
    if (m.version <= version) out.push_back(m);
  }
  return out;
}

class LayerMetadataMigrationTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, LayerMetadataMigrationTest, testing::BothEngines(), testing::EngineName);

TEST_P(LayerMetadataMigrationTest, DocumentsOfSchema18BecomeTypedColumns) {
  {
    const Engine engine = GetParam();
    const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
    ApplyMigrations(*c, UpTo(engine, 18));
    InsertMap(*c, {"home", "Home", 1});
    const auto legacy = [&](const std::string& name, const std::string& kind, const std::string& meta) {
      Statement(*c, "INSERT INTO layers (map_id, name, kind, meta, version, created_ns, updated_ns) "
                    "VALUES ('home', ?, ?, ?, 1, 5, 5)")
          .Bind(1, name).Bind(2, kind).Bind(3, meta).Run();
    };
    const std::string geometry = R"("geometry":{"width_cells":4,"height_cells":3,"resolution_m":0.05,"origin":[-2.5,1.25,0.5]})";
    legacy("occ", "occupancy", "{" + geometry + R"(,"map_server":{"image":"a.pgm","resolution":0.05,"origin":[-2.5,1.25,0.5],)"
                               R"("negate":0,"occupied_thresh":0.65,"free_thresh":0.196,"mode":"raw","mode_given":true},)"
                               R"("ignored_yaml_keys":["comment","robot"]})");
    legacy("prob", "probability", "{" + geometry + R"(,"base":"occ","log_odds":{"hit":0.75,"miss":0.35,"clamp_min":0.1,)"
                                  R"("clamp_max":0.95},"observations":4})");
    legacy("fused", "fused", "{" + geometry + R"(,"op":"xor","operands":[{"layer":"prob","threshold":0.6},)"
                             R"({"layer":"occ","threshold":0.4}]})");
    legacy("rooms", "label", "{" + geometry + R"(,"base":"occ","labels":{"1":"hall","12":"kitchen"}})");
    ApplyMigrations(*c, EmbeddedMigrations(engine));

    const OccupancyLayerMeta o = DecodeOccupancyMeta(*FindLayer(*c, "home", "occ", false));
    EXPECT_EQ(o.geometry.width_cells, 4);
    EXPECT_EQ(o.geometry.origin_x_m, -2.5);
    EXPECT_EQ(o.geometry.origin_yaw_rad, 0.5);
    EXPECT_EQ(o.map_server.mode, MapMode::kRaw);
    EXPECT_TRUE(o.map_server.mode_given);
    EXPECT_EQ(o.map_server.free_thresh, 0.196);
    EXPECT_EQ(o.ignored_yaml_keys, (std::vector<std::string>{"comment", "robot"}));
    const ProbabilityLayerMeta p = DecodeProbabilityMeta(*FindLayer(*c, "home", "prob", false));
    EXPECT_EQ(p.base, "occ");
    EXPECT_EQ(p.log_odds.hit_probability, 0.75);
    EXPECT_EQ(p.log_odds.clamp_min_probability, 0.1);
    EXPECT_EQ(p.observations, 4);
    const FusedLayerMeta f = DecodeFusedMeta(*FindLayer(*c, "home", "fused", false));
    EXPECT_EQ(f.op, FuseOp::kXor);
    ASSERT_EQ(f.operands.size(), 2u);
    EXPECT_EQ(f.operands[0].layer, "prob");
    EXPECT_EQ(f.operands[1].threshold, 0.4);
    const LabelLayerMeta l = DecodeLabelMeta(*FindLayer(*c, "home", "rooms", false));
    EXPECT_EQ(l.base, "occ");
    EXPECT_EQ(l.labels, (std::map<int, std::string>{{1, "hall"}, {12, "kitchen"}}));
    EXPECT_TRUE(FindLayerRow(*c, "home", "prob")->complete);
    EXPECT_FALSE(FindLayerRow(*c, "home", "rooms")->complete);
  }
}

}  // namespace
}  // namespace anchordb::storage
