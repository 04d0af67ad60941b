#include "sim_io/visibility_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sim_io/input_file.hpp"
#include "support/input_error.hpp"

namespace pleat {

namespace {

void append_number(std::string& out, double v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, end);
}

template <class Integer>
void append_integer(std::string& out, Integer v) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, end);
}

}  // namespace

VisibilityCsvWriter::VisibilityCsvWriter(const std::filesystem::path& path,
                                         std::vector<Index> welded_of_input,
                                         const std::vector<Index>& without_surface)
    : m_welded_of_input(std::move(welded_of_input)), m_file(path) {
  for (Index w : m_welded_of_input) m_num_welded = std::max(m_num_welded, Index(w + 1));
  m_without_surface.assign(m_num_welded, 0);
  for (Index w : without_surface)
    if (w < m_num_welded) m_without_surface[w] = 1;
  m_file.stream() << "frame,vertex,front,back,source_frame\n";
}

void VisibilityCsvWriter::add_frame(std::size_t frame, std::int64_t source_frame,
                                    const std::vector<double>& front, const std::vector<double>& back) {
  if (front.size() < m_num_welded || back.size() < m_num_welded)
    throw std::invalid_argument("VisibilityCsvWriter::add_frame: one value per welded vertex and side");
  std::string source;  // the rows' last field and the line's end
  append_integer(source, source_frame);
  source += '\n';
  std::string chunk;
  chunk.reserve(64 * 1024);
  for (std::size_t v = 0; v < m_welded_of_input.size(); ++v) {
    const Index w = m_welded_of_input[v];
    append_integer(chunk, frame);
    chunk += ',';
    append_integer(chunk, v);
    chunk += ',';
    if (!m_without_surface[w]) append_number(chunk, front[w]);
    chunk += ',';
    if (!m_without_surface[w]) append_number(chunk, back[w]);
    chunk += ',';
    chunk += source;
    if (chunk.size() > 60 * 1024) {
      m_file.stream().write(chunk.data(), std::streamsize(chunk.size()));
      chunk.clear();
    }
  }
  m_file.stream().write(chunk.data(), std::streamsize(chunk.size()));
  m_file.check();  // a full disk ends the run here, not after the last frame
}

void VisibilityCsvWriter::close() { m_file.close(); }

void VisibilityCsvWriter::commit() { m_file.commit(); }

std::vector<VisibilityRow> read_visibility_csv(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string text = read_whole_file(path);
  std::vector<VisibilityRow> rows;
  std::size_t begin = 0, line = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string_view row(text.data() + begin, end - begin);
    begin = end + 1;
    ++line;
    if (!row.empty() && row.back() == '\r') row.remove_suffix(1);
    if (line == 1) {
      if (row != "frame,vertex,front,back,source_frame")
        throw InputError(file, "line 1", "expected the header frame,vertex,front,back,source_frame");
      continue;
    }
    if (row.empty()) continue;
    std::string_view fields[5];
    std::size_t count = 0, start = 0;
    for (std::size_t i = 0; i <= row.size(); ++i) {
      if (i == row.size() || row[i] == ',') {
        if (count < 5) fields[count] = row.substr(start, i - start);
        ++count;
        start = i + 1;
      }
    }
    const std::string place = "line " + std::to_string(line);
    if (count != 5) throw InputError(file, place, "expected 5 fields, found " + std::to_string(count));
    VisibilityRow r;
    const auto parse = [&](std::string_view f, auto& value) {
      const auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
      if (ec != std::errc() || p != f.data() + f.size())
        throw InputError(file, place, "'" + std::string(f) + "' is not a number");
    };
    parse(fields[0], r.frame);
    parse(fields[1], r.vertex);
    if (fields[2].empty() != fields[3].empty())
      throw InputError(file, place, "one side's visibility empty, the other's not");
    if (fields[2].empty()) {  // a vertex without surface
      r.front = r.back = std::numeric_limits<double>::quiet_NaN();
    } else {
      parse(fields[2], r.front);
      parse(fields[3], r.back);
      if (!std::isfinite(r.front) || !std::isfinite(r.back))
        throw InputError(file, place, "non-finite visibility");
    }
    parse(fields[4], r.source_frame);
    rows.push_back(r);
  }
  if (line == 0)
    throw InputError(file, "", "empty file (expected the header frame,vertex,front,back,source_frame)");
  return rows;
}

}  // namespace pleat
