// SPDX-License-Identifier: MIT
// Fixture for check_includes.py (never compiled): montecarlo and loop share a floor of host,
// so this include leans sideways and must be named; the campaign below is allowed.

#include "host/campaign/campaign.hpp"
#include "host/loop/stream.hpp"
