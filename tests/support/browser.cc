#include "tests/support/browser.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace mtg::testing {

namespace fs = std::filesystem;
using nlohmann::json;

std::string HeadlessBrowser::executable() {
  if (const char* env = std::getenv("MTG_CHROMIUM"); env != nullptr && *env != '\0') return env;
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    for (const char* name : {"chromium", "chromium-browser"}) {
      const fs::path candidate = fs::path(dir) / name;
      if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return "";
}

HeadlessBrowser::HeadlessBrowser(const fs::path& profile_dir, int width, int height) {
  const std::string exe = executable();
  if (exe.empty()) throw std::runtime_error("no chromium on the PATH");
  fs::create_directories(profile_dir);
  int to[2], from[2];
  if (::pipe(to) != 0 || ::pipe(from) != 0) throw std::runtime_error("pipe() failed");
  const std::vector<std::string> args = {exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                                         "--disable-dev-shm-usage", "--hide-scrollbars", "--remote-debugging-pipe",
                                         "--user-data-dir=" + profile_dir.string(),
                                         "--window-size=" + std::to_string(width) + "," + std::to_string(height),
                                         "about:blank"};
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork() failed");
  if (pid_ == 0) {
    // The browser reads commands on fd 3 and writes replies on fd 4. Move the ends out of the
    // way first, so that dup2 never closes one of them by landing on it.
    const int in = ::fcntl(to[0], F_DUPFD, 10), out = ::fcntl(from[1], F_DUPFD, 10);
    ::dup2(in, 3);
    ::dup2(out, 4);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    for (int fd = 5; fd < 1024; ++fd) ::close(fd);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(to[0]);
  ::close(from[1]);
  to_browser_ = to[1];
  from_browser_ = from[0];
  ::signal(SIGPIPE, SIG_IGN);
  const json targets = call("Target.getTargets", json::object(), false);
  std::string target;
  for (const auto& t : targets["targetInfos"]) {
    if (t["type"] == "page") target = t["targetId"];
  }
  if (target.empty()) target = call("Target.createTarget", {{"url", "about:blank"}}, false)["targetId"];
  session_ = call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}}, false)["sessionId"];
  call("Page.enable");
  call("Runtime.enable");
  call("Emulation.setDeviceMetricsOverride",
       {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}});
}

HeadlessBrowser::~HeadlessBrowser() {
  if (to_browser_ >= 0) ::close(to_browser_);
  if (from_browser_ >= 0) ::close(from_browser_);
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
}

json HeadlessBrowser::call(const std::string& method, const json& params, bool on_page, int timeout_ms) {
  const long id = next_id_++;
  json message = {{"id", id}, {"method", method}, {"params", params}};
  if (on_page) message["sessionId"] = session_;
  const std::string bytes = message.dump() + '\0';
  for (std::size_t sent = 0; sent < bytes.size();) {
    const ssize_t n = ::write(to_browser_, bytes.data() + sent, bytes.size() - sent);
    if (n <= 0) throw std::runtime_error("the browser is gone (" + method + ")");
    sent += static_cast<std::size_t>(n);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    for (std::size_t end; (end = buffer_.find('\0')) != std::string::npos;) {
      const json reply = json::parse(buffer_.substr(0, end), nullptr, false);
      buffer_.erase(0, end + 1);
      if (reply.is_discarded() || !reply.contains("id") || reply["id"] != id) continue;  // events
      if (reply.contains("error")) throw std::runtime_error(method + ": " + reply["error"].dump());
      return reply.value("result", json::object());
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) throw std::runtime_error("the browser did not answer " + method);
    pollfd p{from_browser_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
    char chunk[65536];
    const ssize_t n = ::read(from_browser_, chunk, sizeof chunk);
    if (n <= 0) throw std::runtime_error("the browser closed its pipe during " + method);
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

void HeadlessBrowser::navigate(const std::string& url) {
  call("Page.navigate", {{"url", url}});
  if (!wait_for("document.readyState === 'complete' && location.href !== 'about:blank'", 30000)) {
    throw std::runtime_error("the page did not load: " + url);
  }
}

json HeadlessBrowser::evaluate(const std::string& expression) {
  const json r = call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}, {"awaitPromise", true}});
  if (r.contains("exceptionDetails")) {
    const json& d = r["exceptionDetails"];
    throw std::runtime_error("the page threw: " +
                             (d.contains("exception") ? d["exception"].value("description", d.dump()) : d.dump()));
  }
  return r["result"].value("value", json());
}

bool HeadlessBrowser::wait_for(const std::string& condition, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    try {
      const json v = evaluate("Boolean(" + condition + ")");
      if (v.is_boolean() && v.get<bool>()) return true;
    } catch (const std::runtime_error&) {
      // the page is between documents
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

void HeadlessBrowser::screenshot(const fs::path& file, bool full_page) {
  json params = {{"format", "png"}};
  if (full_page) params["captureBeyondViewport"] = true;
  if (full_page) {
    const json size = evaluate("[document.documentElement.scrollWidth, document.documentElement.scrollHeight]");
    params["clip"] = {{"x", 0}, {"y", 0}, {"width", size[0]}, {"height", size[1]}, {"scale", 1}};
  }
  const std::string b64 = call("Page.captureScreenshot", params)["data"];
  std::string png(b64.size() / 4 * 3 + 3, '\0');
  const int n = EVP_DecodeBlock(reinterpret_cast<unsigned char*>(png.data()),
                                reinterpret_cast<const unsigned char*>(b64.data()), static_cast<int>(b64.size()));
  if (n < 0) throw std::runtime_error("the screenshot is not base64");
  std::size_t size = static_cast<std::size_t>(n);
  for (std::size_t i = b64.size(); i > 0 && b64[i - 1] == '='; --i) --size;  // padding decodes as zeros
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary).write(png.data(), static_cast<std::streamsize>(size));
}

}  // namespace mtg::testing
