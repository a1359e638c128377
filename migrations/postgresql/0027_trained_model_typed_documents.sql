-- 0027: a trained model's options and report are typed documents instead of JSON text (issue 30). PostgreSQL form of
-- sqlite/0027: rows written before keep their text in request_json / report_json.
ALTER TABLE classifiers ADD COLUMN options_document BYTEA;
ALTER TABLE classifiers ADD COLUMN report_document BYTEA;
ALTER TABLE shape_models ADD COLUMN options_document BYTEA;
ALTER TABLE shape_models ADD COLUMN report_document BYTEA;
