#include "services/renderer/encode_pipeline.h"

#include <algorithm>

#include "core/render/image_codec.h"
#include "core/util/log.h"

namespace mtg::services {

EncodePipeline::EncodePipeline(int threads, int max_jobs) : max_jobs_(std::max(1, max_jobs)) {
  for (int i = 0; i < std::max(1, threads); ++i) threads_.emplace_back([this] { work(); });
}

void EncodePipeline::finish_all() {
  std::unique_lock<std::mutex> lock(mutex_);
  job_finished_.wait(lock, [this] { return unfinished_ == 0; });
}

EncodePipeline::~EncodePipeline() {
  finish_all();
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  task_ready_.notify_all();
  for (std::thread& t : threads_) t.join();
}

int EncodePipeline::unfinished() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return unfinished_;
}

void EncodePipeline::submit(std::vector<const cv::Mat*> images, std::string encoding,
                            std::shared_ptr<const void> owner, Done done) {
  if (images.empty()) {
    done({}, nullptr);
    return;
  }
  auto job = std::make_shared<Job>();
  job->images = std::move(images);
  job->encoding = std::move(encoding);
  job->owner = std::move(owner);
  job->done = std::move(done);
  job->bytes.resize(job->images.size());
  job->left = static_cast<int>(job->images.size());
  {
    std::unique_lock<std::mutex> lock(mutex_);
    job_finished_.wait(lock, [this] { return unfinished_ < max_jobs_; });
    ++unfinished_;
    for (std::size_t i = 0; i < job->images.size(); ++i) tasks_.push_back({job, i});
  }
  task_ready_.notify_all();
}

void EncodePipeline::work() {
  for (;;) {
    Task task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      task_ready_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
      if (tasks_.empty()) return;  // stopping, and nothing is left
      task = std::move(tasks_.front());
      tasks_.pop_front();
    }
    Job& job = *task.job;
    std::vector<std::uint8_t> bytes;
    std::exception_ptr error;
    try {
      bytes = render::encode_image(*job.images[task.image], job.encoding);
    } catch (...) {
      error = std::current_exception();
    }
    bool last = false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      job.bytes[task.image] = std::move(bytes);
      if (error && !job.error) job.error = error;
      last = --job.left == 0;
    }
    if (!last) continue;
    // Every image of the job is here, and no other thread touches it any more.
    try {
      job.done(std::move(job.bytes), job.error);
    } catch (const std::exception& e) {
      // done() reports its own failures; one that escapes must not end an encoder thread.
      log::error(std::string("encoder: ") + e.what());
    }
    job.owner.reset();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      --unfinished_;
    }
    job_finished_.notify_all();
  }
}

}  // namespace mtg::services
