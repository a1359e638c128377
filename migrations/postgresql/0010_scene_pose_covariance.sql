-- 0010: the 6x6 covariance of a scene model's camera pose as a JSON array (see sqlite/0010).
ALTER TABLE scene_models ADD COLUMN pose_covariance TEXT;
