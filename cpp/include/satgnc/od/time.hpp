#pragma once
/// @file time.hpp
/// Forwarding header (issue 12): the time functions moved to satgnc/core/time.hpp, namespace
/// satgnc::core. The old satgnc::od names stay available through the using-declarations below.
#include "satgnc/core/time.hpp"

namespace satgnc::od {
using core::gmst_from_utc;
using core::gmst_iau1982;
using core::julian_date;
using core::kMaxUt1MinusUtc;
}  // namespace satgnc::od
