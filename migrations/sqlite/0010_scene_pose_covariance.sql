-- Issue 13: the uncertainty of a scene model's camera pose (its localisation error), a 6x6 covariance in the map
-- frame (ROS order [tx ty tz rx ry rz], m and rad), as a JSON array of 36 numbers, row-major. NULL (models opened
-- before this migration): the server's default (scene_pose_sigma_translation_m / scene_pose_sigma_rotation_rad).
ALTER TABLE scene_models ADD COLUMN pose_covariance TEXT;
