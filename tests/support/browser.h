#pragma once
// A real headless Chromium for page tests, driven over the DevTools protocol on a pipe
// (--remote-debugging-pipe: JSON messages separated by NUL on fds 3 and 4), so no WebSocket
// library, npm package or browser download is needed. Debian's `chromium` is the browser.

#include <sys/types.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace mtg::testing {

class HeadlessBrowser {
 public:
  /// The browser to run: $MTG_CHROMIUM, else chromium on the PATH; "" when there is none.
  static std::string executable();

  /// Starts the browser with a fresh profile in `profile_dir` and attaches to its page.
  /// @throws std::runtime_error when it cannot start or does not answer.
  HeadlessBrowser(const std::filesystem::path& profile_dir, int width = 1300, int height = 1000);
  ~HeadlessBrowser();
  HeadlessBrowser(const HeadlessBrowser&) = delete;
  HeadlessBrowser& operator=(const HeadlessBrowser&) = delete;

  /// Loads `url` and waits for the document to finish loading.
  void navigate(const std::string& url);
  /// Evaluates `expression` in the page (promises awaited) and returns its value.
  /// @throws std::runtime_error with the page's exception text.
  nlohmann::json evaluate(const std::string& expression);
  /// Polls `condition` until it is truthy; returns whether it became so within `timeout_ms`.
  bool wait_for(const std::string& condition, int timeout_ms);
  /// A PNG of the viewport (or the full page) at `file`.
  void screenshot(const std::filesystem::path& file, bool full_page = false);

 private:
  nlohmann::json call(const std::string& method, const nlohmann::json& params = nlohmann::json::object(),
                      bool on_page = true, int timeout_ms = 30000);

  pid_t pid_ = -1;
  int to_browser_ = -1, from_browser_ = -1;
  std::string buffer_;
  std::string session_;
  long next_id_ = 1;
};

}  // namespace mtg::testing
