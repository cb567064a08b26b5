#include "orchestrator/report/sankey.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <sstream>

#include "core/episode/outcomes.h"
#include "core/render/png_writer.h"
#include "core/util/error.h"
#include "core/util/file_bytes.h"
#include "core/util/text.h"

namespace mtg::orchestrator {
namespace {

// Stage order follows the episode; causes by count; outcome success first.
int stage_rank(const std::string& s) {
  const auto stage = episode::stage_from_string(s);
  return stage ? static_cast<int>(*stage) : 99;
}

struct Node {
  std::string id, label;
  int column = 0;
  double value = 0;
  double x = 0, y = 0, h = 0;
  double out_used = 0, in_used = 0;
};

struct Band {
  int source, target;
  double value;
  double x0, y0, x1, y1, t;  // top-left of each end, thickness
};

struct Layout {
  std::vector<Node> nodes;
  std::vector<Band> bands;
  double node_width = 18;
};

std::array<int, 3> colour_of(const Node& n) {  // RGB
  if (n.column == 0) return {70, 110, 180};
  if (n.column == 1) return n.label == "done" ? std::array<int, 3>{70, 160, 90} : std::array<int, 3>{220, 140, 60};
  if (n.label == "success") return {70, 160, 90};
  if (n.column == 3) return {200, 70, 70};
  // Causes are failures: no green among them, so none reads as the success band.
  static const std::array<std::array<int, 3>, 8> kPalette = {{{200, 90, 90}, {150, 90, 180}, {90, 120, 190},
                                                             {190, 160, 60}, {120, 120, 120}, {210, 110, 160},
                                                             {230, 130, 50}, {160, 110, 80}}};
  std::size_t h = 0;
  for (const char c : n.label) h = h * 31 + static_cast<unsigned char>(c);
  return kPalette[h % kPalette.size()];
}

Layout layout(const nlohmann::json& graph, double width, double height) {
  Layout L;
  std::map<std::string, int> index;
  for (const auto& n : graph["nodes"]) {
    Node node;
    node.id = n["id"];
    node.label = n["label"];
    node.column = n["column"];
    node.value = n["value"];
    index[node.id] = static_cast<int>(L.nodes.size());
    L.nodes.push_back(node);
  }
  const double margin_x = 150, margin_top = 40, margin_bottom = 20, gap = 14;
  std::array<double, 4> column_total{}, column_count{};
  for (const Node& n : L.nodes) {
    column_total[static_cast<std::size_t>(n.column)] += n.value;
    column_count[static_cast<std::size_t>(n.column)] += 1;
  }
  double scale = 1e9;
  for (int c = 0; c < 4; ++c) {
    if (column_total[c] <= 0) continue;
    scale = std::min(scale, (height - margin_top - margin_bottom - gap * (column_count[c] - 1)) / column_total[c]);
  }
  std::array<double, 4> cursor;
  cursor.fill(margin_top);
  for (Node& n : L.nodes) {
    n.x = margin_x + n.column * (width - 2 * margin_x - L.node_width) / 3.0;
    n.h = std::max(1.0, n.value * scale);
    n.y = cursor[static_cast<std::size_t>(n.column)];
    cursor[static_cast<std::size_t>(n.column)] += n.h + gap;
  }
  for (const auto& l : graph["links"]) {
    Band b;
    b.source = index.at(l["source"]);
    b.target = index.at(l["target"]);
    b.value = l["value"];
    L.bands.push_back(b);
  }
  // Outgoing bands stacked in target order, incoming in source order: no crossings at the nodes.
  std::vector<int> order(L.bands.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return L.nodes[static_cast<size_t>(L.bands[static_cast<size_t>(a)].target)].y <
           L.nodes[static_cast<size_t>(L.bands[static_cast<size_t>(b)].target)].y;
  });
  for (const int i : order) {
    Band& b = L.bands[static_cast<size_t>(i)];
    Node& s = L.nodes[static_cast<size_t>(b.source)];
    b.t = std::max(1.0, b.value * scale);
    b.x0 = s.x + L.node_width;
    b.y0 = s.y + s.out_used;
    s.out_used += b.t;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return L.nodes[static_cast<size_t>(L.bands[static_cast<size_t>(a)].source)].y <
           L.nodes[static_cast<size_t>(L.bands[static_cast<size_t>(b)].source)].y;
  });
  for (const int i : order) {
    Band& b = L.bands[static_cast<size_t>(i)];
    Node& t = L.nodes[static_cast<size_t>(b.target)];
    b.x1 = t.x;
    b.y1 = t.y + t.in_used;
    t.in_used += b.t;
  }
  return L;
}

std::string rgb(const std::array<int, 3>& c) {
  return "rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
}

// Points along the band's top and bottom cubic curves (for the PNG).
std::vector<cv::Point> band_polygon(const Band& b) {
  std::vector<cv::Point> top, bottom;
  const double xm = (b.x0 + b.x1) / 2;
  for (int i = 0; i <= 24; ++i) {
    const double t = i / 24.0, u = 1 - t;
    const double x = u * u * u * b.x0 + 3 * u * u * t * xm + 3 * u * t * t * xm + t * t * t * b.x1;
    const double y0 = u * u * u * b.y0 + 3 * u * u * t * b.y0 + 3 * u * t * t * b.y1 + t * t * t * b.y1;
    top.emplace_back(static_cast<int>(x), static_cast<int>(y0));
    bottom.emplace_back(static_cast<int>(x), static_cast<int>(y0 + b.t));
  }
  std::reverse(bottom.begin(), bottom.end());
  top.insert(top.end(), bottom.begin(), bottom.end());
  return top;
}

}  // namespace

nlohmann::json sankey_graph(const std::vector<SankeyFlow>& flows) {
  std::map<std::string, double> value;            // node id -> count
  std::map<std::pair<std::string, std::string>, double> links;
  std::map<std::string, std::pair<int, std::string>> info;  // id -> (column, label)
  for (const auto& f : flows) {
    const std::array<std::string, 4> labels = {f.level, f.stage, f.cause, f.outcome};
    for (int c = 0; c < 4; ++c) {
      const std::string id = std::to_string(c) + ":" + labels[static_cast<size_t>(c)];
      value[id] += 1;
      info[id] = {c, labels[static_cast<size_t>(c)]};
      if (c < 3) links[{id, std::to_string(c + 1) + ":" + labels[static_cast<size_t>(c + 1)]}] += 1;
    }
  }
  std::vector<std::string> ids;
  for (const auto& [id, v] : value) ids.push_back(id);
  std::stable_sort(ids.begin(), ids.end(), [&](const std::string& a, const std::string& b) {
    const auto& [ca, la] = info[a];
    const auto& [cb, lb] = info[b];
    if (ca != cb) return ca < cb;
    if (ca == 1) return stage_rank(la) < stage_rank(lb);
    if (ca == 2 || ca == 3) {
      if ((la == "success") != (lb == "success")) return la == "success";
      if (value[a] != value[b]) return value[a] > value[b];
    }
    return la < lb;
  });
  nlohmann::json g;
  g["nodes"] = nlohmann::json::array();
  for (const auto& id : ids) {
    g["nodes"].push_back({{"id", id}, {"label", info[id].second}, {"column", info[id].first}, {"value", value[id]}});
  }
  g["links"] = nlohmann::json::array();
  for (const auto& [st, v] : links) g["links"].push_back({{"source", st.first}, {"target", st.second}, {"value", v}});
  return g;
}

std::string sankey_svg(const nlohmann::json& graph, int width, int height) {
  const Layout L = layout(graph, width, height);
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"12\">";
  const std::array<const char*, 4> heads = {"task level", "stage reached", "cause", "outcome"};
  for (int c = 0; c < 4; ++c) {
    const double x = 150 + c * (width - 300 - L.node_width) / 3.0;
    s << "<text x=\"" << x << "\" y=\"20\" font-weight=\"bold\">" << heads[static_cast<size_t>(c)] << "</text>";
  }
  for (const Band& b : L.bands) {
    const double xm = (b.x0 + b.x1) / 2;
    s << "<path d=\"M" << b.x0 << "," << b.y0 << " C" << xm << "," << b.y0 << " " << xm << "," << b.y1 << " " << b.x1 << ","
      << b.y1 << " L" << b.x1 << "," << b.y1 + b.t << " C" << xm << "," << b.y1 + b.t << " " << xm << "," << b.y0 + b.t
      << " " << b.x0 << "," << b.y0 + b.t << " Z\" fill=\"" << rgb(colour_of(L.nodes[static_cast<size_t>(b.source)]))
      << "\" fill-opacity=\"0.35\" class=\"flow\" data-source=\"" << escape_markup(L.nodes[static_cast<size_t>(b.source)].id)
      << "\" data-target=\"" << escape_markup(L.nodes[static_cast<size_t>(b.target)].id) << "\"><title>"
      << escape_markup(L.nodes[static_cast<size_t>(b.source)].label) << " &#8594; "
      << escape_markup(L.nodes[static_cast<size_t>(b.target)].label) << ": " << b.value << "</title></path>";
  }
  for (const Node& n : L.nodes) {
    s << "<rect x=\"" << n.x << "\" y=\"" << n.y << "\" width=\"" << L.node_width << "\" height=\"" << n.h
      << "\" fill=\"" << rgb(colour_of(n)) << "\"/>";
    const bool left = n.column == 0;
    s << "<text x=\"" << (left ? n.x - 6 : n.x + L.node_width + 6) << "\" y=\"" << n.y + n.h / 2 + 4
      << "\" text-anchor=\"" << (left ? "end" : "start") << "\">" << escape_markup(n.label) << " (" << n.value << ")</text>";
  }
  s << "</svg>";
  return s.str();
}

void sankey_png(const nlohmann::json& graph, const std::string& title, const std::filesystem::path& file, int width,
                int height) {
  const Layout L = layout(graph, width, height);
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  auto bgr = [](const std::array<int, 3>& c) { return cv::Scalar(c[2], c[1], c[0]); };
  for (const Band& b : L.bands) {
    cv::Mat overlay = image.clone();
    cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{band_polygon(b)},
                 bgr(colour_of(L.nodes[static_cast<size_t>(b.source)])), cv::LINE_AA);
    cv::addWeighted(overlay, 0.35, image, 0.65, 0, image);
  }
  for (const Node& n : L.nodes) {
    cv::rectangle(image, cv::Rect(static_cast<int>(n.x), static_cast<int>(n.y), static_cast<int>(L.node_width),
                                  std::max(1, static_cast<int>(n.h))),
                  bgr(colour_of(n)), cv::FILLED);
    const std::string label = n.label + " (" + std::to_string(static_cast<long>(n.value)) + ")";
    int baseline = 0;
    const cv::Size size = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline);
    const int x = n.column == 0 ? static_cast<int>(n.x) - 6 - size.width : static_cast<int>(n.x + L.node_width) + 6;
    cv::putText(image, label, cv::Point(x, static_cast<int>(n.y + n.h / 2 + 5)), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
  }
  cv::putText(image, title + "   (task level -> stage reached -> cause -> outcome)", cv::Point(16, 24),
              cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Through a rename like every other output: cv::imwrite wrote through a link planted at the name.
  write_file_bytes_atomically(file, render::encode_png(image));
}

}  // namespace mtg::orchestrator
