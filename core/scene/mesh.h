#pragma once
// Triangle meshes loaded from the dataset's glb/stl files (assimp), with node transforms
// applied: vertices are in metres in the asset frame (the frame the object's pose refers to).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace mtg::scene {

/// An encoded texture as stored in the glb (PNG/JPEG bytes), decoded only by the renderer.
struct Texture {
  std::string format_hint;            // "png", "jpg", ...
  std::vector<std::uint8_t> encoded;  // compressed bytes
};

struct Material {
  Eigen::Vector4f base_color{1.0f, 1.0f, 1.0f, 1.0f};  // linear RGBA factor
  int texture = -1;                                   // index into Mesh::textures, -1 = none
};

/// A run of triangles that share a material.
struct Primitive {
  std::uint32_t first_index = 0;  // into Mesh::indices
  std::uint32_t index_count = 0;  // a multiple of 3
  int material = 0;               // index into Mesh::materials
};

/// An indexed triangle mesh. positions/normals/uvs are parallel arrays (one entry per vertex).
struct Mesh {
  std::vector<Eigen::Vector3f> positions;  // metres, asset frame, node transforms applied
  std::vector<Eigen::Vector3f> normals;
  std::vector<Eigen::Vector2f> uvs;        // empty when the file has none
  std::vector<std::uint32_t> indices;      // 3 per triangle
  std::vector<Primitive> primitives;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  Eigen::AlignedBox3f bounds;              // of positions

  std::size_t triangle_count() const { return indices.size() / 3; }
};

using MeshHandle = std::shared_ptr<const Mesh>;

struct MeshLoadOptions {
  bool keep_textures = true;  // copy embedded textures (the renderer needs them; geometry does not)
};

/// Loads a glb/gltf/stl/obj file. @throws mtg::Error naming the file if it is missing,
/// unreadable, or holds no triangles.
Mesh load_mesh(const std::filesystem::path& file, const MeshLoadOptions& options = {});

/// Process-wide cache of loaded meshes keyed by canonical path, so an asset used by many
/// instances is read once. Thread-safe. Owned by whoever loads scenes (no global instance).
class MeshCache {
 public:
  explicit MeshCache(MeshLoadOptions options = {}) : options_(options) {}
  /// @throws mtg::Error as load_mesh does (failures are not cached).
  MeshHandle get(const std::filesystem::path& file);

 private:
  MeshLoadOptions options_;
  std::mutex mutex_;
  std::map<std::string, MeshHandle> meshes_;
};

}  // namespace mtg::scene
