-- 0030: the anchordb server that accepted a job (issue 31: several servers on one database). A server marks a job
-- interrupted only when the server that holds it is gone (storage/server_presence.h), not every unfinished job at its
-- start; rows written before have none and count as a gone server's, as every unfinished job did until now.
ALTER TABLE jobs ADD COLUMN server_id TEXT;
