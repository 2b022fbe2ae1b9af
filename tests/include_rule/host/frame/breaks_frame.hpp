// Fixture for tests/include_rule.cmake (never compiled): the frame layer reaching up into a path.
#pragma once

#include "raster/raster_pipeline.hpp"
#include "runtime/cl.hpp"
