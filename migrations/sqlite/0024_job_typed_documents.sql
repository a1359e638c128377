-- 0024: a job's request and result are typed documents (storage/document_codec.h: the blob envelope around the
-- document's kind, codec version and fields) instead of JSON text (issue 30: JSON exists only in the API). Rows
-- written before keep their text in `request` / `result`, which the API shows as it was; a job has one or the other.
ALTER TABLE jobs ADD COLUMN request_document BLOB;
ALTER TABLE jobs ADD COLUMN result_document BLOB;
