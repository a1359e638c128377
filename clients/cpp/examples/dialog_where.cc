// A dialog component: "these are my keys" labels the object of the newest 'added' event, then "where are my keys?"
// is asked and the server's sentence spoken (printed); a question about something never seen shows the typed error.
// With --forget-dry-run (an admin token) it also counts what forgetting would remove, waiting with progress.
// Usage: dialog_where [--host H] [--port P] [--token T] [--map M] [--label keys] [--forget-dry-run 1]
#include <anchordb/client.h>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", token, map = "example", label = "keys";
  int port = 8765;
  bool forget = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--host") host = v;
    else if (a == "--port") port = std::stoi(v);
    else if (a == "--token") token = v;
    else if (a == "--map") map = v;
    else if (a == "--label") label = v;
    else if (a == "--forget-dry-run") forget = v == "1";
  }
  namespace ac = anchordb::client;
  try {
    ac::Client client(host, port, token);
    ac::EventQuery q;
    q.type = "added";
    q.limit = 1000;
    const auto added = client.Events(map, q);
    if (added.empty() || !added.back().instance) {
      std::cerr << "dialog_where: no object was added on map " << map << "\n";
      return 1;
    }
    client.LabelInstance(map, *added.back().instance, label);
    std::cout << "labelled instance " << *added.back().instance << " '" << label << "'\n";
    const ac::WhereAnswer where = client.Where(map, label);
    std::cout << "where: " << where.sentence << " (at " << where.position_m[0] << ", " << where.position_m[1] << ", "
              << where.position_m[2] << " m; " << where.evidence_keyframes.size() << " evidence keyframes)\n";
    try {
      client.Where(map, "unicorn");
    } catch (const ac::ApiError& e) {
      std::cout << "unknown label: " << e.status() << " " << e.code() << " (field " << e.field() << ")\n";
    }
    if (forget) {
      const ac::Job ticket = client.Forget(map, {{"event_max_age_s", 1e9}}, /*dry_run=*/true);
      const ac::Job done = client.WaitJob(ticket.id, [](const ac::Job& j) {
        std::cout << "job " << j.id << " " << j.status << " " << j.stage << " " << static_cast<int>(j.progress * 100) << "%\n";
      });
      std::cout << "forget dry run: " << done.status << " " << done.result.dump() << "\n";
      if (done.status != "succeeded") return 1;
    }
    return where.sentence.empty() ? 1 : 0;
  } catch (const ac::ApiError& e) {
    std::cerr << "dialog_where: the server refused: " << e.status() << " " << e.code() << " " << e.message()
              << (e.field().empty() ? "" : " (field " + e.field() + ")") << "\n";
  } catch (const std::exception& e) {
    std::cerr << "dialog_where: " << e.what() << "\n";
  }
  return 2;
}
