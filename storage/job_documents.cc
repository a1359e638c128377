#include "storage/job_documents.h"

#include "storage/document_codec.h"

namespace anchordb::storage {
namespace {

constexpr std::uint16_t kForgetVersion = 1, kBackupVersion = 1;

void WritePolicy(DocumentWriter& w, const ForgetPolicy& p) {
  w.Bool(p.drop_superseded).Optional(p.keyframe_max_age_s).Real(p.keep_relevance_at_least);
  w.Optional(p.event_max_age_s).Bool(p.vacuum);
}

ForgetPolicy ReadPolicy(DocumentReader& r) {
  ForgetPolicy p;
  p.drop_superseded = r.Bool();
  p.keyframe_max_age_s = r.OptionalReal();
  p.keep_relevance_at_least = r.Real();
  p.event_max_age_s = r.OptionalReal();
  p.vacuum = r.Bool();
  return p;
}

}  // namespace

std::string EncodeForgetRequest(const ForgetRequest& request) {
  DocumentWriter w(DocumentKind::kForgetRequest, kForgetVersion);
  WritePolicy(w, request.policy);
  w.Bool(request.dry_run).Optional(request.now_ns);
  return w.Finish();
}

ForgetRequest DecodeForgetRequest(std::string_view stored, const std::string& what) {
  DocumentReader r(stored, DocumentKind::kForgetRequest, kForgetVersion, what);
  ForgetRequest out;
  out.policy = ReadPolicy(r);
  out.dry_run = r.Bool();
  out.now_ns = r.OptionalInt();
  r.End();
  return out;
}

std::string EncodeForgetReport(const ForgetReport& x) {
  DocumentWriter w(DocumentKind::kForgetReport, kForgetVersion);
  w.Text(x.map_id).Bool(x.dry_run).Int(x.now_ns);
  WritePolicy(w, x.policy);
  w.Ints(x.models_state_dropped).Ints(x.models_deleted).Ints(x.events_deleted).Ints(x.keyframes_deleted);
  w.Ints(x.segments_deleted).Int(x.features_deleted).Int(x.features_deduplicated);
  w.Int(x.keyframes_kept_pinned).Int(x.keyframes_kept_relevant).Int(x.keyframes_kept_referenced);
  w.Int(x.keyframes_kept_open_scene).Int(x.keyframes_of_abandoned_scenes);
  w.Int(x.events_kept_pinned).Int(x.events_kept_labelled).Int(x.events_kept_latest).Int(x.events_kept_pinned_instance);
  w.Int(x.bytes_freed_estimate).Int(x.page_size).Int(x.page_count_before).Int(x.freelist_before);
  w.Int(x.page_count_after).Int(x.freelist_after).Bool(x.committed).Text(x.vacuum_mode);
  w.Int(x.file_bytes_before).Int(x.file_bytes_after).Int(x.page_count_after_vacuum).Int(x.freelist_after_vacuum);
  w.Real(x.seconds);
  return w.Finish();
}

ForgetReport DecodeForgetReport(std::string_view stored, const std::string& what) {
  DocumentReader r(stored, DocumentKind::kForgetReport, kForgetVersion, what);
  ForgetReport x;
  x.map_id = r.Text();
  x.dry_run = r.Bool();
  x.now_ns = r.Int();
  x.policy = ReadPolicy(r);
  x.models_state_dropped = r.Ints();
  x.models_deleted = r.Ints();
  x.events_deleted = r.Ints();
  x.keyframes_deleted = r.Ints();
  x.segments_deleted = r.Ints();
  x.features_deleted = r.Int();
  x.features_deduplicated = r.Int();
  x.keyframes_kept_pinned = r.Int();
  x.keyframes_kept_relevant = r.Int();
  x.keyframes_kept_referenced = r.Int();
  x.keyframes_kept_open_scene = r.Int();
  x.keyframes_of_abandoned_scenes = r.Int();
  x.events_kept_pinned = r.Int();
  x.events_kept_labelled = r.Int();
  x.events_kept_latest = r.Int();
  x.events_kept_pinned_instance = r.Int();
  x.bytes_freed_estimate = r.Int();
  x.page_size = r.Int();
  x.page_count_before = r.Int();
  x.freelist_before = r.Int();
  x.page_count_after = r.Int();
  x.freelist_after = r.Int();
  x.committed = r.Bool();
  x.vacuum_mode = r.Text();
  x.file_bytes_before = r.Int();
  x.file_bytes_after = r.Int();
  x.page_count_after_vacuum = r.Int();
  x.freelist_after_vacuum = r.Int();
  x.seconds = r.Real();
  r.End();
  return x;
}

std::string EncodeBackupRequest(const BackupJobRequest& request) {
  return DocumentWriter(DocumentKind::kBackupRequest, kBackupVersion).Text(request.file).Finish();
}

BackupJobRequest DecodeBackupRequest(std::string_view stored, const std::string& what) {
  DocumentReader r(stored, DocumentKind::kBackupRequest, kBackupVersion, what);
  BackupJobRequest out{r.Text()};
  r.End();
  return out;
}

std::string EncodeBackupReport(const BackupReport& x) {
  DocumentWriter w(DocumentKind::kBackupReport, kBackupVersion);
  w.Text(x.file).Int(x.bytes).Int(x.pages).Int(x.restarts).Text(x.integrity).Real(x.duration_s);
  return w.Finish();
}

BackupReport DecodeBackupReport(std::string_view stored, const std::string& what) {
  DocumentReader r(stored, DocumentKind::kBackupReport, kBackupVersion, what);
  BackupReport x;
  x.file = r.Text();
  x.bytes = r.Int();
  x.pages = r.Int();
  x.restarts = r.SmallInt();
  x.integrity = r.Text();
  x.duration_s = r.Real();
  r.End();
  return x;
}

}  // namespace anchordb::storage
