#pragma once
// The renderer's encoders: drawn images become PNG or JPEG bytes on a pool of threads while the
// drawing thread (the one that owns the GL context) goes on with the next request. Each image is
// a task of its own, so one reply's images are encoded side by side and several replies at once;
// a reply is finished on the thread that encoded its last image. Bytes never depend on which
// thread encoded them (core/render/image_codec.h).

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

namespace mtg::services {

class EncodePipeline {
 public:
  using Bytes = std::vector<std::vector<std::uint8_t>>;
  /// Called once per job, on an encoder thread: the images' bytes in order, or the first error.
  using Done = std::function<void(Bytes bytes, std::exception_ptr error)>;

  /// `threads` encoders (at least one); submit() waits while `max_jobs` jobs are unfinished, so
  /// frames waiting to be encoded never pile up past that.
  EncodePipeline(int threads, int max_jobs);
  /// Finishes every job submitted, then stops the threads.
  ~EncodePipeline();
  EncodePipeline(const EncodePipeline&) = delete;
  EncodePipeline& operator=(const EncodePipeline&) = delete;

  /// Encodes `images` (kept alive by `owner` until `done` returns) as `encoding`. A job without
  /// images is finished at once, on this thread.
  void submit(std::vector<const cv::Mat*> images, std::string encoding, std::shared_ptr<const void> owner, Done done);
  /// Jobs submitted and not yet finished.
  int unfinished() const;
  /// Waits until every job submitted is finished (before what their `done` uses goes away).
  void finish_all();

 private:
  struct Job {
    std::vector<const cv::Mat*> images;
    std::string encoding;
    std::shared_ptr<const void> owner;
    Done done;
    Bytes bytes;
    std::exception_ptr error;
    int left = 0;  // images not yet encoded
  };
  struct Task {
    std::shared_ptr<Job> job;
    std::size_t image = 0;
  };
  void work();

  const int max_jobs_;
  mutable std::mutex mutex_;
  std::condition_variable task_ready_, job_finished_;
  std::deque<Task> tasks_;
  int unfinished_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace mtg::services
