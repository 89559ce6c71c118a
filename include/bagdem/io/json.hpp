// What the JSON documents we write (summary.json, export.json) need: string escaping.
#pragma once
#include <string>

namespace bagdem {

// A string for a JSON document: quotes, backslashes and newlines escaped.
std::string json_escape(const std::string& s);

}  // namespace bagdem
