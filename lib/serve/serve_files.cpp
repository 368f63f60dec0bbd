#include "serve/serve_files.h"

#include <fcntl.h>
#include <httplib.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>

#include "serve/encode_view_model.h"
#include "serve/viewer_assets.h"
#include "splatkit/error.h"

namespace splatkit::serve {

namespace {

constexpr const char* kHost = "127.0.0.1";  // loopback only: the viewer is not a public server

struct ServedFile {
  std::string path;
  uint64_t size = 0;
  std::mutex model_mutex;
  std::shared_ptr<const std::string> model;  // the view model, once made
};

std::string base_name(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

const char* mime_type(std::string_view name) {
  auto ends = [&](std::string_view ext) {
    return name.size() >= ext.size() && name.substr(name.size() - ext.size()) == ext;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js") || ends(".mjs")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".json")) return "application/json";
  if (ends(".png")) return "image/png";
  return "application/octet-stream";
}

std::map<std::string, std::unique_ptr<ServedFile>> check_files(const ServeOptions& o) {
  std::map<std::string, std::unique_ptr<ServedFile>> files;
  for (const std::string& path : o.files) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw_bad_input(path, std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw_bad_input(path, "not a regular file; --serve serves files");
    if (::access(path.c_str(), R_OK) != 0) throw_bad_input(path, std::strerror(errno));
    const std::string name = base_name(path);
    if (name.empty() || name == "." || name == "..")
      throw_usage("--serve needs file names, got '" + path + "'");
    auto file = std::make_unique<ServedFile>();
    file->path = path;
    file->size = static_cast<uint64_t>(st.st_size);
    if (!files.emplace(name, std::move(file)).second)
      throw_usage("two files named '" + name + "': the viewer names files by their base name");
  }
  return files;
}

// The file's bytes through a provider, which lets the library answer Range requests.
void send_file(const ServedFile& f, httplib::Response& res) {
  auto fd = std::shared_ptr<int>(new int(::open(f.path.c_str(), O_RDONLY | O_CLOEXEC)), [](int* p) {
    if (*p >= 0) ::close(*p);
    delete p;
  });
  if (*fd < 0) {
    res.status = 500;
    return;
  }
  res.set_content_provider(
      static_cast<std::size_t>(f.size), "application/octet-stream",
      [fd](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
        char buf[1 << 16];
        while (length > 0) {
          const ssize_t n =
              ::pread(*fd, buf, std::min(length, sizeof buf), static_cast<off_t>(offset));
          if (n <= 0) return false;  // the file shrank or cannot be read: the response aborts
          if (!sink.write(buf, static_cast<std::size_t>(n))) return false;
          offset += static_cast<std::size_t>(n);
          length -= static_cast<std::size_t>(n);
        }
        return true;
      });
}

void send_model(ServedFile& f, const std::string& name, httplib::Response& res) {
  std::shared_ptr<const std::string> model;
  {
    std::lock_guard<std::mutex> lock(f.model_mutex);
    if (!f.model) {
      try {
        f.model = std::make_shared<const std::string>(encode_view_model(f.path, name));
      } catch (const std::exception& e) {
        res.status = 422;
        res.set_content(std::string(e.what()) + "\n", "text/plain; charset=utf-8");
        return;
      }
    }
    model = f.model;
  }
  res.set_content_provider(
      model->size(), "application/octet-stream",
      [model](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
        return sink.write(model->data() + offset, length);
      });
}

void not_found(httplib::Response& res) {
  res.status = 404;
  res.set_content("not found\n", "text/plain; charset=utf-8");
}

}  // namespace

void serve_files(const ServeOptions& o,
                 const std::function<void(const std::string& url)>& on_ready) {
  if (o.port < 0 || o.port > 65535) throw_usage("--port must be in [0, 65535]");
  auto files = check_files(o);
  std::map<std::string, const ViewerAsset*> assets;
  for (std::size_t i = 0; i < kViewerAssetCount; ++i)
    assets[std::string("/") + kViewerAssets[i].path] = &kViewerAssets[i];
  if (assets.count("/index.html")) assets["/"] = assets["/index.html"];
  nlohmann::json listing = {{"files", nlohmann::json::array()}};
  for (const std::string& path : o.files) listing["files"].push_back(base_name(path));
  const std::string listing_text = listing.dump();

  httplib::Server server;
  // SO_REUSEADDR only: the library's default adds SO_REUSEPORT, which would let a second server
  // share a port already taken (each getting some of the connections) instead of failing.
  server.set_socket_options([](socket_t sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  server.Get(R"(/.*)", [&](const httplib::Request& req, httplib::Response& res) {
    const std::string& p = req.path;
    if (auto a = assets.find(p); a != assets.end()) {
      res.set_content(reinterpret_cast<const char*>(a->second->data), a->second->size,
                      mime_type(a->second->path));
      res.set_header("Cache-Control", "no-cache");
      return;
    }
    if (p == "/files.json") {
      res.set_content(listing_text, "application/json");
      return;
    }
    for (const std::string prefix : {"/files/", "/model/"}) {
      if (p.rfind(prefix, 0) != 0) continue;
      auto f = files.find(p.substr(prefix.size()));
      if (f == files.end()) break;
      if (prefix == "/files/")
        send_file(*f->second, res);
      else
        send_model(*f->second, f->first, res);
      return;
    }
    not_found(res);
  });

  // SIGINT and SIGTERM are taken by sigwait() below; blocked before the server's threads start,
  // so that none of them runs a handler.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigset_t previous;
  pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);

  int port = o.port;
  if (port == 0)
    port = server.bind_to_any_port(kHost);
  else if (!server.bind_to_port(kHost, port))
    port = -1;
  if (port <= 0) {
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    throw_output(std::string(kHost) + ":" + std::to_string(o.port),
                 "cannot listen there (the port is taken?)");
  }
  std::thread listener([&] { server.listen_after_bind(); });
  on_ready("http://" + std::string(kHost) + ":" + std::to_string(port) + "/");
  int sig = 0;
  sigwait(&stop_signals, &sig);
  // stop() does nothing before the listening loop runs: a signal at startup waits for it.
  while (!server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  server.stop();
  listener.join();
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
}

}  // namespace splatkit::serve
