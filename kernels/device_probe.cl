/* Probes of what a device does that OpenCL does not report, run once per device by
   host/runtime/device.cpp. device_probe_loops runs one loop of `trips` iterations and writes how
   many it ran: some drivers end every loop of an invocation once all its loops together have run
   a fixed number of iterations (Mesa's llvmpipe: 65535), and pipelines then split their work so
   that no invocation needs more. */

/* done[1] holds 0 (read at run time, so the compiler cannot count the trips ahead); done[0]
   receives the iterations run, done[2] a value that depends on every one of them. */
__kernel void device_probe_loops(uint trips, __global uint* done)
{
    uint step = 1u + done[1], ran = 0, x = 1u;
    for (uint i = 0; i < trips; i += step) {
        x = x * 1664525u + 1013904223u; /* a recurrence no closed form replaces */
        ++ran;
    }
    done[0] = ran;
    done[2] = x;
}

/* w is a buffer over host memory (CL_MEM_USE_HOST_PTR) whose w[1] the host changed after making
   it: w[0] receives w[1] + 1, so the host, reading its own memory after the kernel without a map,
   learns whether the kernel saw its change and whether its write landed there. */
__kernel void device_probe_in_place(__global uint* w)
{
    w[0] = w[1] + 1u;
}
