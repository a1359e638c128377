-- 0027: a trained model's options and report (classifiers, shape models) are typed documents
-- (storage/classifier_documents.h, storage/shape_documents.h) instead of JSON text (issue 30: JSON exists only in the
-- API). Rows written before keep their text in request_json / report_json, which the API shows as it was; a row
-- written since has its documents and empty text there.
ALTER TABLE classifiers ADD COLUMN options_document BLOB;
ALTER TABLE classifiers ADD COLUMN report_document BLOB;
ALTER TABLE shape_models ADD COLUMN options_document BLOB;
ALTER TABLE shape_models ADD COLUMN report_document BLOB;
