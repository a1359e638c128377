-- 0018: a scene model's pose covariance becomes a stored array in the blob envelope of every stored array
-- (storage/blob_codec.h: f64, shape {6, 6}, row-major) instead of a JSON array (issue 30: stored documents are typed;
-- JSON exists only in the API). SQL cannot write the envelope, so rows of earlier schemas keep their JSON array in
-- pose_covariance, which the repository still reads (storage/scene_repository.cc); rows written from now on leave
-- that column NULL.
ALTER TABLE scene_models ADD COLUMN pose_covariance_f64 BLOB;
