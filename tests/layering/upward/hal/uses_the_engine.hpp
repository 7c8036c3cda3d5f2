// SPDX-License-Identifier: MIT
// A fixture of tests/layering (never compiled): a hal header that points up two floors.
#pragma once
#include "excite/hal/field_bus.hpp"
#include "firmware/engine/engine.hpp"
