#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cstring>

#include "core/scene/mesh.h"
#include "core/util/error.h"

namespace mtg::scene {
namespace {

// PreTransformVertices bakes every node transform (ReplicaCAD glbs carry a 0.01 cm->m scale and
// sometimes an axis rotation) into the vertices; without it tables come out 100x too large.
constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_PreTransformVertices | aiProcess_GenSmoothNormals |
                                  aiProcess_SortByPType;

int texture_index_of(const aiScene& scene, const aiMaterial& material) {
  for (const aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
    aiString path;
    if (material.GetTexture(type, 0, &path) != AI_SUCCESS) continue;
    // Embedded textures are referenced as "*<index>".
    if (path.length > 1 && path.data[0] == '*') return std::atoi(path.data + 1);
    // glb files may also reference an embedded texture by its file name.
    for (unsigned i = 0; i < scene.mNumTextures; ++i) {
      if (std::strcmp(scene.mTextures[i]->mFilename.C_Str(), path.C_Str()) == 0) {
        return static_cast<int>(i);
      }
    }
  }
  return -1;
}

Material read_material(const aiScene& scene, const aiMaterial& material) {
  Material out;
  aiColor4D color;
  if (material.Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
      material.Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) {
    out.base_color = Eigen::Vector4f(color.r, color.g, color.b, color.a);
  }
  out.texture = texture_index_of(scene, material);
  if (out.texture >= static_cast<int>(scene.mNumTextures)) out.texture = -1;
  return out;
}

}  // namespace

Mesh load_mesh(const std::filesystem::path& file, const MeshLoadOptions& options) {
  if (!std::filesystem::exists(file)) throw Error(file.string() + ": mesh file not found");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file.string(), kImportFlags);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    throw Error(file.string() + ": cannot load mesh: " + importer.GetErrorString());
  }

  Mesh mesh;
  for (unsigned m = 0; m < scene->mNumMaterials; ++m) {
    mesh.materials.push_back(read_material(*scene, *scene->mMaterials[m]));
  }
  if (mesh.materials.empty()) mesh.materials.emplace_back();

  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh& am = *scene->mMeshes[mi];
    if ((am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;  // points, lines
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
      const aiVector3D& p = am.mVertices[v];
      mesh.positions.emplace_back(p.x, p.y, p.z);
      if (am.mNormals != nullptr) {
        mesh.normals.emplace_back(am.mNormals[v].x, am.mNormals[v].y, am.mNormals[v].z);
      } else {
        mesh.normals.emplace_back(0.0f, 0.0f, 1.0f);
      }
      if (am.mTextureCoords[0] != nullptr) {
        mesh.uvs.emplace_back(am.mTextureCoords[0][v].x, am.mTextureCoords[0][v].y);
      } else {
        mesh.uvs.emplace_back(0.0f, 0.0f);
      }
    }
    Primitive prim;
    prim.first_index = static_cast<std::uint32_t>(mesh.indices.size());
    prim.material = static_cast<int>(am.mMaterialIndex) < static_cast<int>(mesh.materials.size())
                        ? static_cast<int>(am.mMaterialIndex)
                        : 0;
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) mesh.indices.push_back(base + face.mIndices[k]);
    }
    prim.index_count = static_cast<std::uint32_t>(mesh.indices.size()) - prim.first_index;
    if (prim.index_count > 0) mesh.primitives.push_back(prim);
  }
  if (mesh.indices.empty()) throw Error(file.string() + ": mesh has no triangles");

  if (options.keep_textures) {
    for (unsigned t = 0; t < scene->mNumTextures; ++t) {
      const aiTexture& tex = *scene->mTextures[t];
      Texture out;
      out.format_hint = tex.achFormatHint;
      if (tex.mHeight == 0) {  // compressed blob of mWidth bytes
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(tex.pcData);
        out.encoded.assign(bytes, bytes + tex.mWidth);
      }
      mesh.textures.push_back(std::move(out));
    }
  }
  for (const auto& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

MeshHandle MeshCache::get(const std::filesystem::path& file) {
  std::error_code ec;
  auto canonical = std::filesystem::weakly_canonical(file, ec);
  const std::string key = ec ? file.string() : canonical.string();
  {
    std::lock_guard lock(mutex_);
    if (auto it = meshes_.find(key); it != meshes_.end()) return it->second;
  }
  auto loaded = std::make_shared<const Mesh>(load_mesh(file, options_));
  std::lock_guard lock(mutex_);
  return meshes_.emplace(key, std::move(loaded)).first->second;
}

}  // namespace mtg::scene
