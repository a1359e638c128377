// The English reader of spatial descriptions and the knowledge tables: what is understood, and errors that name
// what was not.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/grounding/parser.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace grounding_parser_test {

const CategoryTable& Categories() { return DefaultKnowledge().categories; }
int Id(const char* id) { return Categories().IndexOfId(id); }

TEST(GroundingParserTest, LocatedRelationReference) {
  const ParsedDescription p = ParseSentence("The table is in front of the shelf.", Categories());
  EXPECT_EQ(p.description.located, Id("table"));
  EXPECT_EQ(p.description.relation, Relation::kInFrontOf);
  EXPECT_EQ(p.description.reference, Id("shelf"));
  EXPECT_EQ(p.relation_words, "in front of");
  const ParsedDescription q = ParseSentence("the couch stands to the right of the chest of drawers", Categories());
  EXPECT_EQ(q.description.located, Id("sofa"));
  EXPECT_EQ(q.description.relation, Relation::kRightOf);
  EXPECT_EQ(q.description.reference, Id("chest_of_drawers"));
  EXPECT_EQ(q.reference_words, "chest of drawers");
  EXPECT_EQ(ParseSentence("a plant is right behind the armchair", Categories()).description.relation, Relation::kBehind);
  EXPECT_EQ(ParseSentence("the stool is on the left side of the table", Categories()).description.relation, Relation::kLeftOf);
  EXPECT_EQ(ParseSentence("the stool is in back of the table", Categories()).description.relation, Relation::kBehind);
}

TEST(GroundingParserTest, RelationFirst) {
  const ParsedDescription p = ParseSentence("left of the sofa is the plant", Categories());
  EXPECT_EQ(p.description.located, Id("plant"));
  EXPECT_EQ(p.description.relation, Relation::kLeftOf);
  EXPECT_EQ(p.description.reference, Id("sofa"));
  const ParsedDescription q = ParseSentence("In front of the shelf you can see the chair", Categories());
  EXPECT_EQ(q.description.located, Id("chair"));
  EXPECT_EQ(q.description.reference, Id("shelf"));
  EXPECT_EQ(q.description.relation, Relation::kInFrontOf);
}

std::string MessageOf(const std::function<void()>& f, ErrorCode* code = nullptr, std::string* field = nullptr) {
  try {
    f();
  } catch (const Error& e) {
    if (code) *code = e.code();
    if (field) *field = e.field();
    return e.what();
  }
  return "no error";
}

TEST(GroundingParserTest, ErrorsNameWhatWasNotUnderstood) {
  ErrorCode code = ErrorCode::kInternal;
  std::string field;
  std::string m = MessageOf([] { ParseSentence("the bed is left of the sofa", Categories()); }, &code, &field);
  EXPECT_EQ(code, ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "text");
  EXPECT_NE(m.find("'bed'"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant is next to the sofa", Categories()); });
  EXPECT_NE(m.find("'next to'"), std::string::npos) << m;
  EXPECT_NE(m.find("not in the vocabulary"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant is on the sofa", Categories()); });
  EXPECT_NE(m.find("'on'"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant the sofa left of", Categories()); });
  EXPECT_NE(m.find("does not parse"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant is left of", Categories()); });
  EXPECT_NE(m.find("two pieces of furniture"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant and the sofa", Categories()); });
  EXPECT_NE(m.find("no relation"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("   ", Categories()); });
  EXPECT_NE(m.find("empty"), std::string::npos) << m;
  m = MessageOf([] { ParseSentence("the plant is left of the sofa behind the table", Categories()); });
  EXPECT_NE(m.find("more than one relation"), std::string::npos) << m;
}

TEST(GroundingParserTest, StructuredWords) {
  EXPECT_EQ(ParseRelation("in_front_of"), Relation::kInFrontOf);
  EXPECT_EQ(ParseRelation("to the left of"), Relation::kLeftOf);
  EXPECT_EQ(ParseRelation("Behind"), Relation::kBehind);
  std::string field;
  const std::string m = MessageOf([] { ParseRelation("next_to"); }, nullptr, &field);
  EXPECT_NE(m.find("'next_to'"), std::string::npos) << m;
  EXPECT_EQ(field, "relation");
  EXPECT_EQ(ParseCategory("Couch", Categories(), "located"), Id("sofa"));
  EXPECT_EQ(ParseCategory("chest_of_drawers", Categories(), "located"), Id("chest_of_drawers"));
  const std::string c = MessageOf([] { ParseCategory("bed", Categories(), "reference"); }, nullptr, &field);
  EXPECT_NE(c.find("'bed'"), std::string::npos);
  EXPECT_EQ(field, "reference");
}

TEST(GroundingKnowledgeTest, DefaultsFollowTheThesis) {
  const Knowledge& k = DefaultKnowledge();
  ASSERT_EQ(k.categories.size(), 10);
  for (const char* v : {"chair", "armchair", "sofa"}) EXPECT_EQ(k.categories[Id(v)].nature, Nature::kVehicle) << v;
  for (const char* v : {"shelf", "wardrobe", "cupboard", "chest_of_drawers"}) EXPECT_EQ(k.categories[Id(v)].nature, Nature::kOpposite) << v;
  for (const char* v : {"table", "plant", "stool"}) EXPECT_EQ(k.categories[Id(v)].nature, Nature::kNone) << v;
  // Relative use dominates in the statistics; category (within a nature) plays no part, so vehicles and opposite
  // objects share the numbers where both frames differ; the adaptation schemes lean as named.
  double intrinsic = 0.0;
  int cells = 0;
  for (int o = 0; o < kOrientationCount; ++o) {
    for (int r = 0; r < kRelationCount; ++r) {
      const auto orient = static_cast<Orientation>(o);
      const auto rel = static_cast<Relation>(r);
      intrinsic += k.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, Nature::kVehicle, orient, rel);
      ++cells;
      EXPECT_GT(k.prior.Probability(Scheme::kRelative, Frame::kRelative, Nature::kVehicle, orient, rel), 0.9);
      EXPECT_GT(k.prior.Probability(Scheme::kIntrinsic, Frame::kIntrinsic, Nature::kVehicle, orient, rel), 0.5);
      EXPECT_EQ(k.prior.Probability(Scheme::kUniform, Frame::kIntrinsic, Nature::kVehicle, orient, rel), 0.5);
    }
  }
  EXPECT_LT(intrinsic / cells, 0.5);
  EXPECT_EQ(k.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, Nature::kOpposite, Orientation::kLeft, Relation::kLeftOf),
            k.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, Nature::kVehicle, Orientation::kLeft, Relation::kLeftOf));
  // Pieces without a front are rarely described intrinsically.
  EXPECT_LT(k.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, Nature::kNone, Orientation::kLeft, Relation::kLeftOf), 0.2);
}

TEST(GroundingKnowledgeTest, LoadersRejectBadTablesNamingTheEntry) {
  std::string field;
  std::string m = MessageOf([] { LoadCategoryTable(R"({"categories":[{"id":"bed","nature":"sleepy"}]})"); }, nullptr, &field);
  EXPECT_NE(m.find("bed"), std::string::npos) << m;
  EXPECT_EQ(field, "categories[0].nature");
  m = MessageOf([] { LoadCategoryTable(R"({"categories":[{"id":"a","nature":"none","words":["x"]},{"id":"b","nature":"none","words":["x"]}]})"); });
  EXPECT_NE(m.find("'x'"), std::string::npos) << m;
  // Every frame-prior cell is a probability.
  nlohmann::json prior = nlohmann::json::parse(DefaultFramePriorJson());
  prior["schemes"]["statistical"]["vehicle"]["front"]["behind"] = nullptr;
  m = MessageOf([&] { LoadFramePrior(prior.dump()); }, nullptr, &field);
  EXPECT_EQ(field, "schemes.statistical.vehicle.front.behind") << m;
  prior = nlohmann::json::parse(DefaultFramePriorJson());
  prior["schemes"]["relative"]["opposite"]["left"]["left_of"] = 1.5;
  MessageOf([&] { LoadFramePrior(prior.dump()); }, nullptr, &field);
  EXPECT_EQ(field, "schemes.relative.opposite.left.left_of");
  // A knowledge document may replace only the prior; edits take effect.
  prior = nlohmann::json::parse(DefaultFramePriorJson());
  prior["schemes"]["statistical"]["vehicle"]["left"]["left_of"] = 0.9;
  const Knowledge k = LoadKnowledge(nlohmann::json{{"frame_prior", prior}}.dump());
  EXPECT_EQ(k.categories.size(), 10);
  EXPECT_EQ(k.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, Nature::kVehicle, Orientation::kLeft, Relation::kLeftOf), 0.9);
  EXPECT_NEAR(k.prior.Probability(Scheme::kStatistical, Frame::kRelative, Nature::kVehicle, Orientation::kLeft, Relation::kLeftOf), 0.1, 1e-12);
  EXPECT_THROW(LoadKnowledge(R"({"priors": {}})"), Error);
}

}  // namespace
}  // namespace anchordb::engine::grounding
