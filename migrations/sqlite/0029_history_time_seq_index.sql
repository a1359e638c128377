-- 0029: where-is and every question "where was it at time t" (HistoryAt, storage::ReadWhereInputs) take an object's
-- last history entry at or before t, newest time first and, at equal times, the higher seq: the index now holds seq
-- too, so that entry is the first of a backward index range instead of a sort of the object's entries at that time.
DROP INDEX instance_history_by_time;
CREATE INDEX instance_history_by_time ON instance_history (instance_id, stamp_ns, seq);
