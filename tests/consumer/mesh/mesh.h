// The consumer's own header at the path of a cshapes header (tests/consumer/main.cpp includes both): a cshapes
// header that named its own as "mesh/mesh.h" would find this one and not compile.
#pragma once
namespace consumer {
inline constexpr const char* kGreeting = "consumer";
}  // namespace consumer
