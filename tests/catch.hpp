// Catch2 2.x (Debian 12) or 3.x (Ubuntu 24.04): the same suite builds on both.
#pragma once

#if __has_include(<catch2/catch_all.hpp>)
#include <catch2/catch_all.hpp>
#else
#include <catch2/catch.hpp>
#endif
