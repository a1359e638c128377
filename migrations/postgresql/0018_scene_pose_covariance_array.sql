-- 0018: the pose covariance as a stored array in the blob envelope (see sqlite/0018).
ALTER TABLE scene_models ADD COLUMN pose_covariance_f64 BYTEA;
