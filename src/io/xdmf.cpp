// The XDMF index of results.h5 for ParaView (write_xdmf, io/results_file.hpp): one temporal
// collection of the frames, the balls as points, and the film as triangles when there is one.
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "bagdem/io/results_file.hpp"

namespace bagdem {

namespace {

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s)
    out += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '"' ? "&quot;" : std::string(1, c);
  return out;
}

}  // namespace

void write_xdmf(const std::string& xmf_path, const std::string& h5_name, std::size_t n_particles,
                const std::vector<double>& times, std::size_t film_nodes,
                std::size_t film_triangles) {
  if ((film_nodes == 0) != (film_triangles == 0))
    throw std::invalid_argument("XDMF file " + xmf_path + ": a film needs nodes and triangles");
  const bool film = film_nodes > 0;
  // With a film, each time step is a spatial collection and the particle grid sits one level in.
  const std::string pad = film ? "  " : "";
  const std::string h5 = xml_escape(h5_name), n = std::to_string(n_particles);
  std::ostringstream x;
  // Frame f of an [F M 3] dataset: hyperslab start (f 0 0), stride (1 1 1), count (1 M 3).
  auto slab = [&](std::size_t f, const std::string& m, const std::string& dataset) {
    x << pad << "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"1 " << m << " 3\">\n"
      << pad << "            <DataItem Dimensions=\"3 3\" Format=\"XML\">" << f
      << " 0 0 1 1 1 1 " << m << " 3</DataItem>\n"
      << pad << "            <DataItem Dimensions=\"" << times.size() << ' ' << m
      << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ':' << dataset
      << "</DataItem>\n"
      << pad << "          </DataItem>\n";
  };
  auto frame_slab = [&](std::size_t f, const char* name) {
    slab(f, n, std::string("/frames/") + name);
  };
  auto constant = [&](const char* name, const char* type, int precision) {
    x << pad << "        <Attribute Name=\"" << name
      << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      << pad << "          <DataItem Dimensions=\"" << n << "\" NumberType=\"" << type
      << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << h5 << ":/particles/" << name
      << "</DataItem>\n"
      << pad << "        </Attribute>\n";
  };
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"" << (film ? "bag" : "particles")
    << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t f = 0; f < times.size(); ++f) {
    char time[32];  // shortest text that reads back as exactly times[f]
    const std::string_view t(time, std::to_chars(time, time + sizeof time, times[f]).ptr - time);
    if (film)
      x << "      <Grid Name=\"frame " << f
        << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
        << "        <Time Value=\"" << t << "\"/>\n"
        << "        <Grid Name=\"particles\" GridType=\"Uniform\">\n";
    else
      x << "      <Grid Name=\"frame " << f << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << t << "\"/>\n";
    x << pad << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
      << "\"/>\n"
      << pad << "        <Geometry GeometryType=\"XYZ\">\n";
    frame_slab(f, "position");
    x << pad << "        </Geometry>\n";
    for (const char* name : {"velocity", "angular_velocity"}) {
      x << pad << "        <Attribute Name=\"" << name
        << "\" AttributeType=\"Vector\" Center=\"Node\">\n";
      frame_slab(f, name);
      x << pad << "        </Attribute>\n";
    }
    constant("radius", "Float", 8);
    constant("material", "Int", 4);
    x << pad << "      </Grid>\n";
    if (film) {
      // The triangles, the whole [T 3] dataset, also through a hyperslab: ParaView's XDMF reader
      // caches a grid whose topology is a plain HDF item and reuses it while the text of the
      // geometry's first item stays the same, and complains that a hyperslab has none.
      const std::string tri = std::to_string(film_triangles);
      x << "        <Grid Name=\"film\" GridType=\"Uniform\">\n"
        << "          <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << tri << "\">\n"
        << "            <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << tri
        << " 3\" NumberType=\"Int\" Precision=\"4\">\n"
        << "              <DataItem Dimensions=\"3 2\" Format=\"XML\">0 0 1 1 " << tri
        << " 3</DataItem>\n"
        << "              <DataItem Dimensions=\"" << tri
        << " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << h5
        << ":/film/triangles</DataItem>\n"
        << "            </DataItem>\n"
        << "          </Topology>\n"
        << "          <Geometry GeometryType=\"XYZ\">\n";
      slab(f, std::to_string(film_nodes), "/film/position");
      x << "          </Geometry>\n"
        << "        </Grid>\n"
        << "      </Grid>\n";
    }
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";

  // Write beside the target, then rename: a reader never sees a half-written file.
  const std::string part = xmf_path + ".part";
  std::ofstream out(part, std::ios::binary | std::ios::trunc);
  out << x.str();
  out.close();
  if (!out) throw std::runtime_error("cannot write XDMF file " + part);
  std::error_code ec;
  std::filesystem::rename(part, xmf_path, ec);
  if (ec)
    throw std::runtime_error("cannot rename " + part + " to " + xmf_path + ": " + ec.message());
}

}  // namespace bagdem
