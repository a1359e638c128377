#pragma once
// JSON <-> the typed requests and results of FurnitureService (the /furniture-graphs routes). Parsers are strict:
// unknown keys, wrong types and non-finite numbers are Error(kInvalidArgument) naming the field; the checks that
// need the service's settings or a graph's knowledge (ranges, category words) are the service's.
#include "schema/json_io.h"
#include "services/furniture/furniture_types.h"

namespace anchordb::api {

using json::Json;

// {viewpoint: {position: [x, y(, z)], heading_rad}, furniture: [{id?, position, extent?, yaw_rad?, categories}],
//  params?: {n_best, sigma, edge_max_gap_m, relation_sharpness, adaptation, frame_prior}}
services::CreateGraphRequest ParseCreateGraph(const Json& body);
// {text} or {located, relation, reference}; text at most max_text_length characters.
services::DescriptionRequest ParseDescription(const Json& body, std::size_t max_text_length);
// {located, reference}: vertex ids.
services::ProduceRequest ParseProduce(const Json& body);
// {seq?, located, reference}: which pieces a held description meant (vertex ids).
services::ResolveRequest ParseResolve(const Json& body);

Json ToJson(const services::GraphView& view);
Json ToJson(const std::vector<services::GraphSummary>& graphs);  // {"furniture_graphs": [...]}
Json ToJson(const services::GroundingResult& result);
Json ToJson(const services::HypothesisList& list);
Json ToJson(const services::Utterance& utterance);

}  // namespace anchordb::api
