// Text fields of CSV files (RFC 4180): a field holding a comma, a double quote or a line break is written
// between double quotes, with its quotes doubled, so that a label such as "a,b" stays one column.
#pragma once

#include <string>

namespace cshapes {

// The field as it must appear in a CSV line: unchanged when it needs no quoting, else quoted.
std::string csv_field(const std::string& text);

}  // namespace cshapes
