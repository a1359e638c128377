-- 3D shape models of furniture (thesis 4.1, SPEC §4.7): the model blob (engine/shapes/shape_model.h: parameters,
-- SHOT codebook, per category and codeword the vote-direction bins), the training options (without the samples) and
-- the training report as JSON. Not per map: a shape model is knowledge, like a classifier.
CREATE TABLE shape_models (
  name         TEXT PRIMARY KEY,
  created_ns   INTEGER NOT NULL,
  model        BLOB NOT NULL,
  request_json TEXT NOT NULL,
  report_json  TEXT NOT NULL
);
