#include "core/render/codec_module.h"

#include <dlfcn.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/util/error.h"

namespace mtg::render {
namespace {

namespace fs = std::filesystem;

using DecodeFn = bool (*)(const std::uint8_t*, std::size_t, cv::Mat*);
using EncodeFn = bool (*)(const char*, const cv::Mat*, const std::vector<int>*, std::vector<std::uint8_t>*);

struct Module {
  DecodeFn decode = nullptr;
  EncodeFn encode = nullptr;
};

constexpr const char* kModuleName = "libmtg_imgcodecs.so";

// The module beside the running program (build/bin), else wherever the loader finds it
// ($LD_LIBRARY_PATH, an installed copy).
Module load() {
  std::error_code ec;
  const fs::path beside = fs::read_symlink("/proc/self/exe", ec).parent_path() / kModuleName;
  void* handle = nullptr;
  std::string why;
  if (!ec && fs::exists(beside)) {
    handle = ::dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) why = ::dlerror();
  }
  if (handle == nullptr) handle = ::dlopen(kModuleName, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* err = ::dlerror();
    throw Error(std::string("image codecs: cannot load ") + kModuleName + " (looked beside the program" +
                (ec ? "" : " in " + beside.parent_path().string()) + " and on the library path): " +
                (why.empty() ? (err ? err : "not found") : why));
  }
  Module m;
  m.decode = reinterpret_cast<DecodeFn>(::dlsym(handle, "mtg_imgcodecs_decode_color"));
  m.encode = reinterpret_cast<EncodeFn>(::dlsym(handle, "mtg_imgcodecs_encode"));
  if (m.decode == nullptr || m.encode == nullptr) {
    throw Error(std::string("image codecs: ") + kModuleName + " lacks its entry points (another mtg build's?)");
  }
  return m;
}

const Module& module() {
  static const Module m = load();  // thread-safe once; a failure throws again on the next call
  return m;
}

}  // namespace

cv::Mat decode_color_image(std::span<const std::uint8_t> bytes) {
  cv::Mat out;
  if (bytes.empty()) return out;
  module().decode(bytes.data(), bytes.size(), &out);
  return out;
}

bool encode_with_imgcodecs(const std::string& extension, const cv::Mat& image, std::vector<std::uint8_t>& out,
                           const std::vector<int>& params) {
  return module().encode(extension.c_str(), &image, &params, &out);
}

bool imgcodecs_loaded() {
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    if (line.find("libopencv_imgcodecs") != std::string::npos) return true;
  }
  return false;
}

}  // namespace mtg::render
