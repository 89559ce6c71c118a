// JSON documents: what the ones we write (summary.json, export.json, map.json) need, string
// escaping, and reading one back, always through a JSON library (nlohmann-json), never by text search.
#pragma once
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace bagdem {

// A string for a JSON document: quotes, backslashes and newlines escaped.
std::string json_escape(const std::string& s);

// A number for a JSON document, printf's %.<digits>g; "null" when it is not finite (NaN, inf).
std::string json_number_text(double x, int digits = 10);

// The JSON document in a file, its keys in the file's order; InputError naming the file when it is
// missing or not JSON.
nlohmann::ordered_json read_json(const std::filesystem::path& path);

// The number at `pointer` ("/structure/band_response_rms_m") of a document; NaN when it is absent
// or not a number.
double json_number(const nlohmann::ordered_json& doc, const std::string& pointer);

}  // namespace bagdem
