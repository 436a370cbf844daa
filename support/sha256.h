// SHA-256 (FIPS 180-4) of bytes and of a file's content: what the caches (data/cache.h) and the options' keys
// (support/option_fields.h) name content by.
#pragma once

#include <string>

namespace cshapes {

// SHA-256 of `bytes`, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);
// SHA-256 of a file's content; throws naming the file when it cannot be read.
std::string file_content_hash(const std::string& path);

}  // namespace cshapes
