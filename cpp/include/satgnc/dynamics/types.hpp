#pragma once
/// @file types.hpp
/// Forwarding header: the fixed-size types live in satgnc/core/types.hpp.
#include "satgnc/core/types.hpp"
