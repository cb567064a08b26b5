// Figures of the web viewer (issue: "time to first paint of the overview and of an episode page
// for a 10,000-episode run, memory of mtg view"): starts `mtg view` on a run folder, loads pages
// in headless Chromium and reads the page's own clock (window.mtgRendered: the moment the page
// drew its content, performance.now() from the navigation's start; first-contentful-paint).

#include <CLI/CLI.hpp>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <regex>
#include <thread>
#include <tuple>

#include "orchestrator/run/results_db.h"
#include "tests/support/browser.h"
#include "tests/support/process.h"

namespace {

namespace fs = std::filesystem;

long status_kib(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  }
  return -1;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mtg_bench_view: page times and memory of mtg view on a run"};
  std::string run, images_run, work = "/tmp/mtg_bench_view";
  int repeat = 3;
  app.add_option("--run", run, "run folder")->required();
  app.add_option("--images-run", images_run, "a run with images: its episode page is timed with every image loaded");
  app.add_option("--work", work, "scratch folder (browser profile, logs)");
  app.add_option("--repeat", repeat, "loads per page");
  CLI11_PARSE(app, argc, argv);
  using mtg::testing::HeadlessBrowser;
  if (HeadlessBrowser::executable().empty()) {
    std::printf("  skipped: no chromium\n");
    return 0;
  }
  fs::remove_all(work);
  fs::create_directories(work);
  const auto rows = mtg::orchestrator::read_results(fs::path(run) / "results.sqlite");
  std::int64_t bytes = 0;
  for (const auto& e : fs::directory_iterator(run)) {
    if (e.path().extension() == ".lcmlog") bytes += static_cast<std::int64_t>(e.file_size());
  }
  std::printf("  run %s: %zu episodes, recording %.0f MiB\n", fs::path(run).filename().c_str(), rows.size(),
              static_cast<double>(bytes) / (1 << 20));

  const auto started = std::chrono::steady_clock::now();
  mtg::testing::ChildProcess view({mtg::testing::bin("mtg"), "view", run, "--port", "0"}, work + "/view.log");
  int port = -1;
  for (int i = 0; i < 400 && port < 0; ++i) {
    std::ifstream in(work + "/view.log");
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    std::smatch m;
    if (std::regex_search(text, m, std::regex(R"(:(\d+)/)"))) port = std::stoi(m[1]);
    else std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (port < 0) {
    std::fprintf(stderr, "mtg view did not start (%s/view.log)\n", work.c_str());
    return 1;
  }
  const double listen_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  const std::string base = "http://127.0.0.1:" + std::to_string(port) + "/";
  HeadlessBrowser browser(fs::path(work) / "profile");

  // One page load: navigate, wait for the page's content, read its clock.
  auto load = [&](const std::string& url, const std::string& mark) {
    browser.navigate("data:text/html,blank");
    browser.navigate(url);
    if (!browser.wait_for("window." + mark, 120000)) throw std::runtime_error("no " + mark + " on " + url);
    return browser.evaluate("window." + mark).get<double>();
  };
  const std::string episode = rows.empty() ? "0" : to_string(rows[rows.size() / 2].episode_id);
  const std::string episode_url = base + "#/run/" + fs::path(run).filename().string() + "/episode/" + episode;
  // The first episode page right after start waits for the recording's index.
  const double cold_episode = load(episode_url, "mtgRendered");
  struct Page {
    const char* name;
    std::string url, mark;
  };
  const std::vector<Page> pages = {
      {"overview (tables)", base, "mtgRendered"},
      {"overview with Sankey", base, "mtgSankey"},
      {"episode list (100 rows)", base + "#/run/" + fs::path(run).filename().string() + "/episodes", "mtgRendered"},
      {"list sorted by IP, searched", base + "#/run/" + fs::path(run).filename().string() +
                                          "/episodes?q=L2&sort=ip&order=desc", "mtgRendered"},
      {"episode page", episode_url, "mtgRendered"},
      {"comparison (agents paired)", base + "#/comparison?a=" + fs::path(run).filename().string(), "mtgRendered"}};
  std::printf("  mtg view listening after %.0f ms\n", listen_ms);
  std::printf("  episode page, first load after start (waits for the index): %.0f ms\n", cold_episode);
  for (const Page& p : pages) {
    std::vector<double> t;
    for (int i = 0; i < repeat; ++i) t.push_back(load(p.url, p.mark));
    std::printf("  %-26s drawn after %.0f ms (median of %d loads, from navigation start)\n", p.name, median(t), repeat);
  }
  const double fcp = browser.evaluate(
      "(performance.getEntriesByName('first-contentful-paint')[0] || {startTime: -1}).startTime").get<double>();
  std::printf("  first contentful paint of the last page: %.0f ms\n", fcp);
  std::printf("  mtg view memory: %.1f MiB resident now, %.1f MiB peak\n", status_kib(view.pid(), "VmRSS") / 1024.0,
              status_kib(view.pid(), "VmHWM") / 1024.0);
  view.kill(SIGTERM);

  // An episode page with images: drawn, and every image loaded (polled every 50 ms).
  auto load_with_images = [&](const std::string& url) {
    browser.navigate("data:text/html,blank");
    browser.navigate(url);
    const std::string done = "window.mtgRendered && document.querySelectorAll('.step img').length > 0 && "
                             "[...document.querySelectorAll('.step img')].every((i) => i.complete)";
    if (!browser.wait_for("window.mtgRendered", 120000)) throw std::runtime_error("no page at " + url);
    browser.evaluate("document.querySelectorAll('img').forEach((i) => { i.loading = 'eager'; })");
    if (!browser.wait_for(done, 120000)) throw std::runtime_error("images never loaded at " + url);
    return std::make_pair(browser.evaluate("performance.now()").get<double>(),
                          browser.evaluate("document.querySelectorAll('.step img').length").get<int>());
  };
  if (!images_run.empty()) {
    mtg::testing::ChildProcess iview({mtg::testing::bin("mtg"), "view", images_run, "--port", "0"}, work + "/iview.log");
    const int iport = mtg::testing::port_in_log(work + "/iview.log", 20000);
    const auto irows = mtg::orchestrator::read_results(fs::path(images_run) / "results.sqlite");
    if (iport > 0 && !irows.empty()) {
      const std::string url = "http://127.0.0.1:" + std::to_string(iport) + "/#/run/" +
                              fs::path(images_run).filename().string() + "/episode/" +
                              to_string(irows[irows.size() / 2].episode_id);
      load_with_images(url);  // the index
      std::vector<double> t;
      int n = 0;
      for (int i = 0; i < repeat; ++i) std::tie(t.emplace_back(), n) = load_with_images(url);
      std::printf("  episode page with its %d images, all loaded: %.0f ms (median of %d)\n", n, median(t), repeat);
    }
    iview.kill(SIGTERM);
  }

  // mtg export of the whole run: time, size, and its pages from file://.
  const fs::path site = fs::path(work) / "site";
  const auto t0 = std::chrono::steady_clock::now();
  mtg::testing::ChildProcess exporter({mtg::testing::bin("mtg"), "export", run, "--out", site.string()},
                                      work + "/export.log");
  if (exporter.wait(3600000) != 0) {
    std::fprintf(stderr, "mtg export failed (%s/export.log)\n", work.c_str());
    return 1;
  }
  const double export_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::uintmax_t site_bytes = 0;
  std::size_t site_files = 0;
  for (const auto& f : fs::recursive_directory_iterator(site)) {
    if (f.is_regular_file()) {
      site_bytes += f.file_size();
      ++site_files;
    }
  }
  std::printf("  mtg export: %.1f s, %zu files, %.0f MiB (%.1f KiB per episode)\n", export_s, site_files,
              static_cast<double>(site_bytes) / (1 << 20), rows.empty() ? 0.0 : site_bytes / 1024.0 / rows.size());
  const std::string file_base = "file://" + fs::absolute(site / "index.html").string() + "#/run/" +
                                fs::path(run).filename().string();
  for (const Page& p : std::vector<Page>{{"exported overview", file_base, "mtgRendered"},
                                         {"exported list, sorted+searched", file_base + "/episodes?q=L2&sort=ip&order=desc",
                                          "mtgRendered"},
                                         {"exported episode page", file_base + "/episode/" + episode, "mtgRendered"}}) {
    std::vector<double> t;
    for (int i = 0; i < repeat; ++i) t.push_back(load(p.url, p.mark));
    std::printf("  %-30s drawn after %.0f ms (median of %d loads, from file://)\n", p.name, median(t), repeat);
  }
  return 0;
}
