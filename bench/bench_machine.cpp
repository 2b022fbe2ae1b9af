// The machine's load and identity from /proc (see bench_machine.hpp).
#include "bench_machine.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>

namespace clvis::bench {

Load read_load()
{
    Load l;
    std::ifstream in("/proc/loadavg");
    double one = 0, five = 0, fifteen = 0;
    if (in >> one >> five >> fifteen) l = {one, five, fifteen};
    return l;
}

std::string to_string(const Load& load)
{
    if (!load.known()) return "unknown";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f %.2f %.2f", load.one, load.five, load.fifteen);
    return buf;
}

Machine read_machine()
{
    Machine m;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    m.cores = n > 0 ? int(n) : 0;
    m.cpu_model = "unknown";
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) != 0) continue;
        auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        auto begin = line.find_first_not_of(" \t", colon + 1);
        if (begin != std::string::npos) m.cpu_model = line.substr(begin);
        break;
    }
    return m;
}

} // namespace clvis::bench
