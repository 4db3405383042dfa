// `cmkit view MODELS [--results R]`: exports the scene to a temporary folder
// and serves it with the built web viewer (viewer/dist) on 127.0.0.1 with a
// tiny built-in HTTP server (GET only, files only, never a non-loopback
// address).
#include <fmt/core.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "cmkit/tools/export.h"
#include "commands.h"
#include "data_paths.h"
#include "model_loading.h"
#include "option_checks.h"
#include "trace_loading.h"

namespace cmkit::cli {
namespace {

namespace fs = std::filesystem;

/// Default port of the viewer (0 lets the system choose).
constexpr int kDefaultPort = 8765;
/// Largest request head read (bytes); longer requests are refused.
constexpr std::size_t kMaxRequestBytes = 16 * 1024;
/// How long to wait for a client to send its request (milliseconds).
constexpr int kRequestTimeoutMs = 5000;
/// Poll period of the accept loop, to honour --exit-after (milliseconds).
constexpr int kAcceptPollMs = 200;
/// Pending connections queued by listen().
constexpr int kListenBacklog = 16;
/// File names of the exported scene in the temporary folder.
constexpr const char* kSceneFile = "scene.glb";
constexpr const char* kResultsFile = "results.txt";
constexpr const char* kAuditFile = "audit.json";

struct ViewOptions {
  std::string models;
  std::string queries;
  std::string results;
  std::string audit;  ///< --audit: a `cmkit audit --json` file
  std::string materials;
  bool noProc = false;  ///< --no-proc
  MeshCliOptions mesh;  ///< --up, --scale, --contents (mesh files)
  std::string viewerDir;
  int port = kDefaultPort;
  double exitAfter = 0;
};

/// Removes the temporary scene folder on every way out of the command.
class TempDirGuard {
 public:
  explicit TempDirGuard(fs::path dir) : dir_(std::move(dir)) {}
  ~TempDirGuard() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  TempDirGuard(const TempDirGuard&) = delete;
  TempDirGuard& operator=(const TempDirGuard&) = delete;

 private:
  fs::path dir_;
};

/// Closes a file descriptor (when valid) on every way out.
class FdGuard {
 public:
  explicit FdGuard(int fd) : fd_(fd) {}
  ~FdGuard() {
    if (fd_ >= 0) ::close(fd_);
  }
  FdGuard(const FdGuard&) = delete;
  FdGuard& operator=(const FdGuard&) = delete;

 private:
  int fd_;
};

/// Ctrl-C (SIGINT) and SIGTERM as a file descriptor to poll: the signals are
/// blocked for the process and read from the descriptor instead, so the
/// serve loop ends normally and cleans up (no handler, no global flag).
/// -1 when the system refuses (then the default action applies).
int openStopSignals() {
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGINT);
  sigaddset(&mask, SIGTERM);
  if (::sigprocmask(SIG_BLOCK, &mask, nullptr) != 0) return -1;
  const int fd = ::signalfd(-1, &mask, SFD_CLOEXEC);
  if (fd < 0) ::sigprocmask(SIG_UNBLOCK, &mask, nullptr);
  return fd;
}

std::string defaultViewerDir() {
  if (const char* env = std::getenv("CMKIT_VIEWER_DIR")) return env;
  // An installed tree: PREFIX/share/cmkit/viewer.
  if (const fs::path share = installedDataDir();
      !share.empty() && fs::exists(share / "viewer" / "index.html"))
    return (share / "viewer").string();
  // A build-tree binary: the source tree's viewer/dist above it.
  if (const fs::path dist = findAboveExecutable(fs::path("viewer") / "dist" / "index.html"); !dist.empty())
    return dist.parent_path().string();
  return "viewer/dist";
}

const char* contentType(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript";
  if (ext == ".css") return "text/css";
  if (ext == ".gltf") return "model/gltf+json";
  if (ext == ".glb") return "model/gltf-binary";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".txt") return "text/plain; charset=utf-8";
  return "application/octet-stream";
}

void sendAll(int fd, const std::string& data) {
  std::size_t sent = 0;
  while (sent < data.size()) {
    const ssize_t n = ::send(fd, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;
    sent += std::size_t(n);
  }
}

void respond(int fd, int status, const char* reason, const char* type, const std::string& body) {
  sendAll(fd, fmt::format("HTTP/1.0 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n"
                          "Cache-Control: no-store\r\nConnection: close\r\n\r\n",
                          status, reason, type, body.size()) +
                  body);
}

// Serves one request: files from the scene folder first, then the viewer.
void serveClient(int fd, const fs::path& sceneDir, const fs::path& viewerDir) {
  std::string request;
  char buf[4096];
  while (request.find("\r\n\r\n") == std::string::npos && request.size() < kMaxRequestBytes) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, kRequestTimeoutMs) <= 0) return;
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) return;
    request.append(buf, std::size_t(n));
  }
  std::istringstream line(request.substr(0, request.find("\r\n")));
  std::string method, target;
  line >> method >> target;
  if (method != "GET" && method != "HEAD") {
    respond(fd, 405, "Method Not Allowed", "text/plain", "GET only\n");
    return;
  }
  std::string path = target.substr(0, target.find('?'));
  if (path.empty() || path.front() != '/' || path.find("..") != std::string::npos ||
      path.find('\\') != std::string::npos) {
    respond(fd, 400, "Bad Request", "text/plain", "bad path\n");
    return;
  }
  if (path == "/") path = "/index.html";
  const std::string rel = path.substr(1);
  for (const fs::path& root : {sceneDir, viewerDir}) {
    const fs::path file = root / rel;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) continue;
    std::ifstream in(file, std::ios::binary);
    std::ostringstream body;
    body << in.rdbuf();
    respond(fd, 200, "OK", contentType(file), method == "HEAD" ? std::string() : body.str());
    return;
  }
  respond(fd, 404, "Not Found", "text/plain", "not found\n");
}

int runView(const ViewOptions& o) {
  const fs::path viewerDir = o.viewerDir.empty() ? defaultViewerDir() : o.viewerDir;
  if (!fs::is_regular_file(viewerDir / "index.html")) {
    fmt::print(stderr,
               "cmkit view: the built viewer is not in {} (no index.html). Build it with\n"
               "  npm ci --prefix viewer && npm run build --prefix viewer\n"
               "or point --viewer-dir (or CMKIT_VIEWER_DIR) at it.\n",
               viewerDir.string());
    return kExitBadInput;
  }
  auto scene = loadSceneForCli(o.models, o.materials, o.noProc, o.mesh, o.queries, o.results);
  if (!scene) {
    fmt::print(stderr, "cmkit view: {}\n", scene.error().toString());
    return kExitBadInput;
  }
  // The audit's findings are served as written; the viewer reads them (and
  // says in its status line when it cannot).
  std::string audit;
  if (!o.audit.empty()) {
    auto text = readCliText(o.audit);
    if (!text) {
      fmt::print(stderr, "cmkit view: {}\n", text.error().toString());
      return kExitBadInput;
    }
    const std::size_t first = text->find_first_not_of(" \t\r\n");
    if (first == std::string::npos || (*text)[first] != '{') {
      fmt::print(stderr, "cmkit view: {}:1: not a JSON object (write one with cmkit audit MAP --json FILE)\n",
                 o.audit);
      return kExitBadInput;
    }
    audit = std::move(*text);
  }

  // Export into a fresh temporary folder.
  std::string tmpl = (fs::temp_directory_path() / "cmkit-view-XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) {
    fmt::print(stderr, "cmkit view: cannot make a temporary folder\n");
    return kExitBadInput;
  }
  const fs::path sceneDir = tmpl;
  const TempDirGuard removeSceneDir(sceneDir);
  // From here on Ctrl-C / SIGTERM only end the serve loop (taken before the
  // URL is printed: whoever reads it may stop the server at once).
  const int stopSignals = openStopSignals();
  const FdGuard closeStopSignals(stopSignals);
  ExportOptions exportOptions;
  exportOptions.placements = scene->placements;
  exportOptions.classNames = scene->classNames;
  if (Status s = saveScene((sceneDir / kSceneFile).string(), scene->models, scene->traces, exportOptions);
      !s) {
    fmt::print(stderr, "cmkit view: {}\n", s.error().toString());
    return kExitBadInput;
  }
  {
    std::ofstream out(sceneDir / kResultsFile, std::ios::binary);
    for (const TraceRecord& r : scene->traces) out << r.queryLine << '\n' << r.resultLine << '\n';
  }
  if (!audit.empty()) std::ofstream(sceneDir / kAuditFile, std::ios::binary) << audit;

  // Listen on the loopback address only.
  const int server = ::socket(AF_INET, SOCK_STREAM, 0);
  const FdGuard closeServer(server);
  if (server < 0) {
    fmt::print(stderr, "cmkit view: cannot open a socket\n");
    return kExitBadInput;
  }
  const int yes = 1;
  ::setsockopt(server, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(std::uint16_t(o.port));
  if (::bind(server, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(server, kListenBacklog) != 0) {
    fmt::print(stderr, "cmkit view: cannot listen on 127.0.0.1:{} (in use? try --port 0)\n", o.port);
    return kExitBadInput;
  }
  socklen_t len = sizeof addr;
  ::getsockname(server, reinterpret_cast<sockaddr*>(&addr), &len);
  fmt::print("scene: {}\nviewer: http://127.0.0.1:{}/?model={}&results={}{}\n", sceneDir.string(),
             ntohs(addr.sin_port), kSceneFile, kResultsFile,
             audit.empty() ? "" : std::string("&audit=") + kAuditFile);
  std::fflush(stdout);

  const auto start = std::chrono::steady_clock::now();
  while (o.exitAfter <= 0 ||
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < o.exitAfter) {
    pollfd p[2] = {{server, POLLIN, 0}, {stopSignals, POLLIN, 0}};
    if (::poll(p, stopSignals >= 0 ? 2 : 1, kAcceptPollMs) <= 0) continue;
    if (stopSignals >= 0 && (p[1].revents & POLLIN)) {
      fmt::print("stopping: removing {}\n", sceneDir.string());
      break;
    }
    if (!(p[0].revents & POLLIN)) continue;
    const int client = ::accept(server, nullptr, nullptr);
    if (client < 0) continue;
    serveClient(client, sceneDir, viewerDir);
    ::close(client);
  }
  return 0;
}

}  // namespace

void registerView(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  auto* cmd = app.add_subcommand(
      "view",
      "Export the collision models (and traces) to a temporary folder and serve them with the web\n"
      "viewer on http://127.0.0.1:PORT (loopback only; prints the URL). In the browser: drag to\n"
      "orbit, wheel to zoom, toggle contents kinds and internal edges, click a trace to see its\n"
      "contact (fraction, point, normal, features; the entity hit for `cmkit query --world`\n"
      "results). A .map's entities are placed by their keys: click a model, or pick one from the\n"
      "Entities list, to see its name, class and origin; a toggle hides all but the world model.\n"
      "--audit FILE shows the findings of `cmkit audit MAP --json FILE` (numbered markers coloured\n"
      "by severity, a list; click one for what it is and the path that reached it).\n"
      "Stop with Ctrl-C.\n"
      "The viewer must be built once: npm ci --prefix viewer && npm run build --prefix viewer\n\n"
      "Examples:\n"
      "  cmkit view maps/lt4.map\n"
      "  cmkit query maps/box_room.map q.txt -o r.txt\n"
      "  cmkit query tests/data/maps/two_halls.map q.txt --world -o r.txt   (entity= in each result)\n"
      "  cmkit view maps/box_room.map --queries q.txt --results r.txt --port 8080\n"
      "  cmkit audit maps/lt4.map --json lt4_audit.json; cmkit view maps/lt4.map --audit lt4_audit.json");
  cmd->add_option("MODELS", o->models, "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...)")
      ->required();
  cmd->add_option("--queries", o->queries, "query file whose traces to show (with --results)");
  cmd->add_option("--results", o->results,
                  "results of the queries; without --queries, query lines each followed by its result line");
  cmd->add_option("--audit", o->audit, "findings to show: the JSON of cmkit audit MAP --json FILE");
  cmd->add_option("--port", o->port, "port on 127.0.0.1 (0: any free port)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  cmd->add_option("--viewer-dir", o->viewerDir, "the built viewer (default: viewer/dist of the source tree)");
  cmd->add_option("--exit-after", o->exitAfter, "stop serving after this many seconds (0: never)")
      ->check(finiteAtLeast(0));
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addMeshOptions(cmd, o->mesh);
  cmd->callback([o] {
    if (int rc = runView(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
