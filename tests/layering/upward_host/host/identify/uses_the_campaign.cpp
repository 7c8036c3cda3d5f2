// SPDX-License-Identifier: MIT
// Fixture for check_includes.py (never compiled): identify sits below campaign in host's
// order, so this include points up and must be named.

#include "host/campaign/campaign.hpp"
#include "host/measures/gain_directions.hpp"
