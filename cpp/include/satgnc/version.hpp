#pragma once
/// @file version.hpp
namespace satgnc {
/// Library version (semantic versioning).
inline constexpr const char* version = "0.1.0";
}  // namespace satgnc
