#include "core/render/gl/scene_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "core/render/codec_module.h"
#include "core/render/image_codec.h"
#include "core/render/mark_layout.h"
#include "core/render/overlay.h"
#include "core/render/visibility.h"
#include "core/render/view.h"
#include "core/util/error.h"

namespace mtg::render {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
uniform mat4 u_clip_from_mesh;
uniform mat3 u_normal_to_world;
out vec3 v_normal;
out vec2 v_uv;
void main() {
  gl_Position = u_clip_from_mesh * vec4(a_position, 1.0);
  v_normal = u_normal_to_world * a_normal;
  v_uv = a_uv;
})";

// A head light plus a sky term: enough shading to read shapes, no shadows (the agent needs to
// see items, not a photograph). Normals may face either way in the data, hence abs().
// ReplicaCAD's textures carry the scan's own light baked in, so the inside of a fridge or a
// cupboard is near black in the texture itself, and no light multiplies it back: dark texels
// are lifted towards a luminance floor first (as a torch or the fridge's lamp would show them),
// which leaves every texel brighter than the floor as it was (docs/render.md, "Light").
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 v_normal;
in vec2 v_uv;
uniform vec4 u_colour;
uniform bool u_textured;
uniform sampler2D u_texture;
uniform vec3 u_light;
out vec4 o_colour;
void main() {
  vec4 c = u_colour;
  if (u_textured) c *= texture(u_texture, v_uv);
  float albedo = dot(c.rgb, vec3(0.299, 0.587, 0.114));
  c.rgb += vec3(max(0.0, 0.50 - albedo) * 0.8);
  vec3 n = normalize(v_normal);
  float light = 0.30 + 0.50 * abs(dot(n, u_light)) + 0.20 * (0.5 + 0.5 * n.z);
  o_colour = vec4(min(c.rgb * light, vec3(1.0)), 1.0);
})";

unsigned compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw Error(std::string("render: shader does not compile: ") + log);
  }
  return s;
}

unsigned link_program() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) throw Error("render: shader program does not link");
  return p;
}

// Decodes an embedded texture (PNG/JPEG bytes) to RGBA, no larger than max_size on either edge.
cv::Mat decode_texture(const scene::Texture& t, int max_size) {
  std::vector<std::uint8_t> bytes = without_color_profile(t.encoded);  // no libpng warning per texture
  cv::Mat bgr = decode_color_image(bytes);
  if (bgr.empty()) return bgr;
  const int edge = std::max(bgr.cols, bgr.rows);
  if (edge > max_size) {
    const double f = static_cast<double>(max_size) / edge;
    cv::resize(bgr, bgr, cv::Size(), f, f, cv::INTER_AREA);
  }
  cv::Mat rgba;
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  return rgba;
}

}  // namespace

struct SceneRenderer::GpuMesh {
  GLuint vao = 0, vbo = 0, ebo = 0;
  std::vector<scene::Primitive> primitives;
  std::vector<scene::Material> materials;
  std::vector<GLuint> textures;  // per Mesh::textures entry; 0 when it could not be decoded
  std::int64_t triangles = 0;
};

SceneRenderer::SceneRenderer(const GlContext&, const scene::Scene& scene, const graph::SceneGraph& graph,
                             RendererOptions options)
    : options_(options) {
  program_ = link_program();
  parts_.resize(graph.objects.size());
  for (const graph::ObjectId i : graph.objects.ids()) {
    const scene::ObjectInstance* inst = scene.find(graph.objects[i].name);
    if (inst == nullptr) continue;
    for (const scene::Part& part : inst->parts) {
      if (part.movable_link) continue;
      // A missing render mesh falls back to the collision mesh, untextured, so the object is
      // still where the agent expects it.
      const scene::MeshHandle& mesh = part.render ? part.render : part.collision;
      if (!mesh) continue;
      parts_[i].push_back({upload(mesh), part.render ? part.T_OA : part.T_OC});
    }
  }
  glEnable(GL_DEPTH_TEST);
  if (glGetError() != GL_NO_ERROR) throw Error("render: uploading the scene's meshes failed (GL error)");
}

SceneRenderer::~SceneRenderer() {
  for (auto& [_, m] : meshes_) {
    glDeleteVertexArrays(1, &m->vao);
    glDeleteBuffers(1, &m->vbo);
    glDeleteBuffers(1, &m->ebo);
    for (const GLuint t : m->textures) {
      if (t != 0) glDeleteTextures(1, &t);
    }
  }
  if (framebuffer_ != 0) {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteRenderbuffers(1, &depth_);
  }
  glDeleteProgram(program_);
}

const SceneRenderer::GpuMesh* SceneRenderer::upload(const scene::MeshHandle& mesh) {
  auto& slot = meshes_[mesh.get()];
  if (slot) return slot.get();
  auto m = std::make_unique<GpuMesh>();
  const std::size_t n = mesh->positions.size();
  std::vector<float> vertices;
  vertices.reserve(n * 8);
  for (std::size_t v = 0; v < n; ++v) {
    const Eigen::Vector3f& p = mesh->positions[v];
    const Eigen::Vector3f nrm = v < mesh->normals.size() ? mesh->normals[v] : Eigen::Vector3f::UnitZ();
    const Eigen::Vector2f uv = v < mesh->uvs.size() ? mesh->uvs[v] : Eigen::Vector2f::Zero();
    vertices.insert(vertices.end(), {p.x(), p.y(), p.z(), nrm.x(), nrm.y(), nrm.z(), uv.x(), uv.y()});
  }
  glGenVertexArrays(1, &m->vao);
  glBindVertexArray(m->vao);
  glGenBuffers(1, &m->vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m->vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(),
               GL_STATIC_DRAW);
  glGenBuffers(1, &m->ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m->ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh->indices.size() * sizeof(std::uint32_t)),
               mesh->indices.data(), GL_STATIC_DRAW);
  const GLsizei stride = 8 * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(6 * sizeof(float)));
  glBindVertexArray(0);

  m->primitives = mesh->primitives;
  m->materials = mesh->materials;
  m->triangles = static_cast<std::int64_t>(mesh->triangle_count());
  for (const scene::Texture& t : mesh->textures) {
    const cv::Mat rgba = decode_texture(t, options_.max_texture_size);
    GLuint id = 0;
    if (!rgba.empty()) {
      glGenTextures(1, &id);
      glBindTexture(GL_TEXTURE_2D, id);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data);
      glGenerateMipmap(GL_TEXTURE_2D);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
      texture_bytes_ += static_cast<std::int64_t>(rgba.total() * 4 * 4 / 3);  // with mipmaps
    }
    m->textures.push_back(id);
  }
  slot = std::move(m);
  return slot.get();
}

bool SceneRenderer::has_geometry(graph::ObjectId o) const { return !parts_.at(o).empty(); }

void SceneRenderer::ensure_framebuffer(int width, int height) {
  if (framebuffer_ != 0 && width == fb_width_ && height == fb_height_) return;
  if (framebuffer_ == 0) {
    glGenFramebuffers(1, &framebuffer_);
    glGenRenderbuffers(1, &colour_);
    glGenRenderbuffers(1, &depth_);
  }
  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw Error("render: a " + std::to_string(width) + "x" + std::to_string(height) +
                " framebuffer is not supported by this GL");
  }
  fb_width_ = width;
  fb_height_ = height;
}

Frame SceneRenderer::render(const Camera& camera, const IdVector<graph::ObjectId, Eigen::Isometry3d>& poses_W,
                            const IdVector<graph::ObjectId, bool>& draw) {
  MTG_DEMAND(poses_W.size() == parts_.size() && draw.size() == parts_.size(), "one pose per graph object");
  ensure_framebuffer(camera.width, camera.height);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, camera.width, camera.height);
  const cv::Scalar& bg = options_.background;
  glClearColor(static_cast<float>(bg[2] / 255), static_cast<float>(bg[1] / 255), static_cast<float>(bg[0] / 255), 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(program_);
  const GLint u_clip = glGetUniformLocation(program_, "u_clip_from_mesh");
  const GLint u_normal = glGetUniformLocation(program_, "u_normal_to_world");
  const GLint u_colour = glGetUniformLocation(program_, "u_colour");
  const GLint u_textured = glGetUniformLocation(program_, "u_textured");
  const GLint u_light = glGetUniformLocation(program_, "u_light");
  glUniform1i(glGetUniformLocation(program_, "u_texture"), 0);
  glActiveTexture(GL_TEXTURE0);
  // Light from behind the camera and a little above it.
  const Eigen::Vector3f light =
      (camera.X_WC.linear().col(2) + 0.6 * camera.X_WC.linear().col(1)).normalized().cast<float>();
  glUniform3f(u_light, light.x(), light.y(), light.z());
  const Eigen::Matrix4f clip_from_world = camera.clip_from_world();

  Frame frame;
  for (const graph::ObjectId i : parts_.ids()) {
    if (!draw[i]) continue;
    for (const DrawPart& part : parts_[i]) {
      const Eigen::Affine3d X_WA = poses_W[i] * part.T_OA;
      const Eigen::Matrix4f clip_from_mesh = clip_from_world * X_WA.matrix().cast<float>();
      const Eigen::Matrix3f normal_to_world = X_WA.linear().inverse().transpose().cast<float>();
      glUniformMatrix4fv(u_clip, 1, GL_FALSE, clip_from_mesh.data());
      glUniformMatrix3fv(u_normal, 1, GL_FALSE, normal_to_world.data());
      glBindVertexArray(part.mesh->vao);
      for (const scene::Primitive& prim : part.mesh->primitives) {
        const scene::Material& mat = part.mesh->materials.at(static_cast<std::size_t>(prim.material));
        const bool textured = mat.texture >= 0 && part.mesh->textures.at(static_cast<std::size_t>(mat.texture)) != 0;
        glUniform4f(u_colour, mat.base_color.x(), mat.base_color.y(), mat.base_color.z(), 1.0f);
        glUniform1i(u_textured, textured ? 1 : 0);
        if (textured) glBindTexture(GL_TEXTURE_2D, part.mesh->textures[static_cast<std::size_t>(mat.texture)]);
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(prim.index_count), GL_UNSIGNED_INT,
                       reinterpret_cast<void*>(static_cast<std::uintptr_t>(prim.first_index) * sizeof(std::uint32_t)));
        frame.triangles += prim.index_count / 3;
      }
    }
  }
  glBindVertexArray(0);
  // Read back as BGR straight into the returned image: the GL packs pixels in the copy it makes
  // anyway. Reading RGBA into a new buffer and converting it took twice as long on a GPU (H200:
  // 1.1 ms against 0.5 ms per 640x480 frame; docs/render.md "On a GPU").
  frame.image.create(camera.height, camera.width, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, camera.width, camera.height, GL_BGR, GL_UNSIGNED_BYTE, frame.image.data);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR) {
    throw Error("render: drawing failed (GL error " + std::to_string(err) + ")");
  }
  cv::flip(frame.image, frame.image, 0);  // GL rows start at the bottom
  return frame;
}

std::vector<const cv::Mat*> images_in_reply_order(const std::vector<ViewImages>& views) {
  std::vector<const cv::Mat*> out;
  for (const ViewImages& v : views) {
    out.push_back(&v.plain);
    if (!v.marked.empty()) out.push_back(&v.marked);
    for (const ZoomImage& z : v.zooms) out.push_back(&z.marked);
  }
  return out;
}

namespace {

// The poses of every object in `s`, and which the plan draws.
struct DrawList {
  IdVector<graph::ObjectId, Eigen::Isometry3d> poses;
  IdVector<graph::ObjectId, bool> draw;
};

DrawList draw_list(const graph::SceneGraph& g, const episode::WorldState& s, const ViewPlan& plan) {
  const std::size_t n = g.objects.size();
  DrawList d{IdVector<graph::ObjectId, Eigen::Isometry3d>(n), IdVector<graph::ObjectId, bool>(n, !plan.only.valid())};
  for (const graph::ObjectId i : g.objects.ids()) d.poses[i] = object_pose(g, s, i);
  for (const graph::ObjectId h : plan.hidden) d.draw[h] = false;
  if (plan.only.valid()) d.draw[plan.only] = true;
  for (const graph::ObjectId o : plan.only_with) d.draw[o] = true;
  return d;
}

}  // namespace

namespace {

// The names of zoom frames: each zoom's place in the observation's list of zooms.
std::vector<std::string> zoom_names(const std::vector<std::size_t>& zooms, std::size_t first) {
  std::vector<std::string> out;
  for (const std::size_t z : zooms) out.push_back(zoom_name(first + z));
  return out;
}

}  // namespace

ViewImages draw_view(SceneRenderer& renderer, const graph::SceneGraph& g, const episode::WorldState& s,
                     const ViewPlan& plan, bool with_marks, const SceneGeometry& geometry) {
  if (plan.only.valid() && !renderer.has_geometry(plan.only)) {
    throw Error("render: object " + g.objects[plan.only].name +
                " has no mesh to draw (its mesh files are missing from the dataset)");
  }
  const DrawList d = draw_list(g, s, plan);
  Frame frame = renderer.render(plan.camera, d.poses, d.draw);
  if (!plan.faded.empty()) {
    IdVector<graph::ObjectId, bool> without = d.draw;
    for (const graph::ObjectId f : plan.faded) without[f] = false;
    const Frame behind = renderer.render(plan.camera, d.poses, without);
    cv::addWeighted(frame.image, kFadedVisibility, behind.image, 1.0 - kFadedVisibility, 0.0, frame.image);
    frame.triangles += behind.triangles;
  }
  ViewImages out;
  out.triangles = frame.triangles;
  if (plan.numbered.number > 0) {
    // A close-up's number, on the object's own pixels (its neighbours, faded or not, aside).
    const Camera pass = at_resolution(plan.camera, std::max(1, plan.camera.width / kMarkPassScale),
                                      std::max(1, plan.camera.height / kMarkPassScale));
    const IdImage ids = draw_id_view(g, geometry, s, pass, {}, plan.numbered.object).image;
    const MarkLayout layout = layout_item_marks(ids, kMarkPassScale, plan.camera, {plan.numbered});
    frame.image = annotate(frame.image, plan.camera, Marks{}, &layout);
  }
  if (with_marks) {
    if (!plan.marks.regions.empty()) {
      // Placement targets by the same rules as items: crowded numbers go to zoomed views.
      const TargetMarksPlan targets = plan_target_marks(plan.camera, plan.marks.regions);
      for (const TargetZoom& z : targets.zooms) {
        Frame zoomed = renderer.render(z.camera, d.poses, d.draw);
        out.triangles += zoomed.triangles;
        Marks here;
        here.regions = z.regions;
        here.fixtures = plan.marks.fixtures;  // those the zoom shows
        ZoomImage image;
        image.marked = annotate(zoomed.image, z.camera, here, nullptr, z.frames,
                                zoom_names(z.frame_zooms, plan.first_zoom), &z.layout);
        for (const PlacedTarget& t : z.layout.placed) image.numbers.push_back(t.number);
        image.targets = true;
        out.zooms.push_back(std::move(image));
      }
      out.zoomed_targets = targets.layout.crowded;
      out.marked = annotate(frame.image, plan.camera, plan.marks, nullptr, targets.frames,
                            zoom_names(targets.frame_zooms, plan.first_zoom), &targets.layout);
    } else if (plan.marks.items.empty()) {
      out.marked = annotate(frame.image, plan.camera, plan.marks);
    } else {
      const ItemMarksPlan marks = plan_item_marks(g, geometry, s, plan.camera, plan.marks.items, plan.hidden);
      for (const MarkedZoom& z : marks.zooms) {
        Frame zoomed = renderer.render(z.view.camera, d.poses, d.draw);
        out.triangles += zoomed.triangles;
        ZoomImage image;
        image.marked = annotate(zoomed.image, z.view.camera, Marks{}, &z.layout, z.regions,
                                zoom_names(z.region_zooms, plan.first_zoom));
        for (const PlacedMark& m : z.layout.placed) image.numbers.push_back(m.number);
        out.zooms.push_back(std::move(image));
      }
      for (const ItemMark& m : marks.layout.crowded) out.zoomed.push_back(m.number);
      out.marked = annotate(frame.image, plan.camera, plan.marks, &marks.layout, marks.regions,
                            zoom_names(marks.region_zooms, plan.first_zoom));
    }
  }
  out.plain = std::move(frame.image);
  return out;
}

}  // namespace mtg::render
