#pragma once
// JSON of the anchored features capability (SPEC §5 routes /features, /codebooks, /bow).
#include "api/router.h"  // Eigen before httplib

#include "api/http_api.h"
#include "services/features/feature_types.h"

namespace anchordb::api {

// {"type", "stamp"?, "features": [{"descriptor": [...], "anchor_m": [x,y,z], "keyframe"?}]}
services::FeatureBatch ParseFeatureBatch(const Json& body);
Json ToJson(const services::FeatureBatchResult& r);
// type=, near=x,y,z & radius=, bbox=min_x,min_y,min_z,max_x,max_y,max_z (or the 2-D min_x,min_y,max_x,max_y: every
// height), since=, until=, keyframe=, after=, limit=, descriptors=true|false.
services::FeatureQuery ParseFeatureQuery(const httplib::Request& req);
Json ToJson(const services::FeaturePage& page);
// {"type", "words", "seed"?}
services::CodebookRequest ParseCodebookRequest(const Json& body);
Json ToJson(const services::CodebookView& book, bool centres);
// type= and one of near=&radius=, bbox=, polygon=x,y;x,y;x,y; since=, until=.
services::BowQuery ParseBowQuery(const httplib::Request& req);
Json ToJson(const services::BowResult& r);
// {"types": [...]?} (default fpfh, shot, spd)
services::ExtractRequest ParseExtractRequest(const Json& body);
Json ToJson(const services::ExtractResult& r);

// A codebook job's request {type, words, seed} and result {type, words, dims, features, assigned}.
Json ToJson(const storage::CodebookJobRequest& request);
Json ToJson(const storage::CodebookJobResult& result);

}  // namespace anchordb::api
