/* Oclgrind 21.10's uninitialised-value checker on a recycled buffer, in plain OpenCL (no clvis).
 * Its shadow memory is kept per buffer index and never dropped when a buffer is released; the next
 * clCreateBuffer gets the released index, and kernelBegin allocates fresh shadow (poisoned, the
 * buffer's size) only where none exists for that index. So a buffer that takes the index of a
 * smaller released one keeps the old, smaller shadow: kernel stores past the old size are lost from
 * it, and loads there read as uninitialised, though the kernel wrote every element.
 *
 * recycled_buffer 0: a 1024-element buffer filled by one kernel and read by another: clean.
 * recycled_buffer 1: the same after a 16-element buffer was filled by a kernel and released:
 *                    Oclgrind reports the 1008 elements past the old size (1000 reports kept).
 * Runs on the platform named Oclgrind (OCL_ICD_VENDORS as the oclgrind CTest entries set it), checks
 * the values it reads back (every element 7) and exits 1 naming any OpenCL call that failed.
 * Run by tests/oclgrind/recycled_buffer.cmake, with and without keep_buffers.c preloaded. */
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* source =
    "__kernel void fill(__global ulong* k, uint n)\n"
    "{ uint i = get_global_id(0); if (i < n) k[i] = 7; }\n"
    "__kernel void readback(__global const ulong* k, __global ulong* out, uint n)\n"
    "{ uint i = get_global_id(0); if (i < n) out[i] = min(k[i], (ulong)9); }\n";

static void check(cl_int status, const char* call)
{
    if (status != CL_SUCCESS) {
        fprintf(stderr, "recycled_buffer: %s failed (%d)\n", call, (int)status);
        exit(1);
    }
}

/* The first device of the platform whose name contains "Oclgrind"; exits 1 when there is none. */
static cl_device_id oclgrind_device(void)
{
    cl_platform_id platforms[16];
    cl_uint count = 0;
    check(clGetPlatformIDs(16, platforms, &count), "clGetPlatformIDs");
    for (cl_uint i = 0; i < count && i < 16; ++i) {
        char name[256] = "";
        check(clGetPlatformInfo(platforms[i], CL_PLATFORM_NAME, sizeof name - 1, name, NULL), "clGetPlatformInfo");
        if (strstr(name, "Oclgrind")) {
            cl_device_id device;
            check(clGetDeviceIDs(platforms[i], CL_DEVICE_TYPE_ALL, 1, &device, NULL), "clGetDeviceIDs");
            return device;
        }
    }
    fprintf(stderr, "recycled_buffer: no OpenCL platform named Oclgrind (OCL_ICD_VENDORS?)\n");
    exit(1);
}

/* Fills `n` elements of `keys` with 7 by the kernel `fill` and waits. */
static void fill(cl_command_queue queue, cl_kernel kernel, cl_mem keys, cl_uint n)
{
    size_t global = n;
    check(clSetKernelArg(kernel, 0, sizeof keys, &keys), "clSetKernelArg(fill)");
    check(clSetKernelArg(kernel, 1, sizeof n, &n), "clSetKernelArg(fill)");
    check(clEnqueueNDRangeKernel(queue, kernel, 1, NULL, &global, NULL, 0, NULL, NULL), "clEnqueueNDRangeKernel(fill)");
    check(clFinish(queue), "clFinish");
}

int main(int argc, char** argv)
{
    if (argc != 2 || (strcmp(argv[1], "0") && strcmp(argv[1], "1"))) {
        fprintf(stderr, "usage: recycled_buffer 0|1 (1: a small buffer used and released first)\n");
        return 2;
    }
    int recycle = argv[1][0] == '1';
    cl_int status;
    cl_device_id device = oclgrind_device();
    cl_context context = clCreateContext(NULL, 1, &device, NULL, NULL, &status);
    check(status, "clCreateContext");
    cl_command_queue queue = clCreateCommandQueue(context, device, 0, &status);
    check(status, "clCreateCommandQueue");
    cl_program program = clCreateProgramWithSource(context, 1, &source, NULL, &status);
    check(status, "clCreateProgramWithSource");
    check(clBuildProgram(program, 1, &device, "", NULL, NULL), "clBuildProgram");
    cl_kernel filler = clCreateKernel(program, "fill", &status);
    check(status, "clCreateKernel(fill)");
    cl_kernel reader = clCreateKernel(program, "readback", &status);
    check(status, "clCreateKernel(readback)");

    enum { small_n = 16, n = 1024 };
    if (recycle) { /* its index is handed to the next buffer created */
        cl_mem small = clCreateBuffer(context, CL_MEM_READ_WRITE, small_n * sizeof(cl_ulong), NULL, &status);
        check(status, "clCreateBuffer(small)");
        fill(queue, filler, small, small_n);
        check(clReleaseMemObject(small), "clReleaseMemObject(small)");
    }
    cl_mem keys = clCreateBuffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_ulong), NULL, &status);
    check(status, "clCreateBuffer(keys)");
    cl_mem out = clCreateBuffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_ulong), NULL, &status);
    check(status, "clCreateBuffer(out)");
    fill(queue, filler, keys, n);
    cl_uint count = n;
    size_t global = n;
    check(clSetKernelArg(reader, 0, sizeof keys, &keys), "clSetKernelArg(readback)");
    check(clSetKernelArg(reader, 1, sizeof out, &out), "clSetKernelArg(readback)");
    check(clSetKernelArg(reader, 2, sizeof count, &count), "clSetKernelArg(readback)");
    check(clEnqueueNDRangeKernel(queue, reader, 1, NULL, &global, NULL, 0, NULL, NULL), "clEnqueueNDRangeKernel(readback)");
    static cl_ulong values[n];
    check(clEnqueueReadBuffer(queue, out, CL_TRUE, 0, sizeof values, values, 0, NULL, NULL), "clEnqueueReadBuffer");
    for (int i = 0; i < n; ++i)
        if (values[i] != 7) {
            fprintf(stderr, "recycled_buffer: element %d reads %llu, not 7\n", i, (unsigned long long)values[i]);
            return 1;
        }
    clReleaseMemObject(out);
    clReleaseMemObject(keys);
    clReleaseKernel(reader);
    clReleaseKernel(filler);
    clReleaseProgram(program);
    clReleaseCommandQueue(queue);
    clReleaseContext(context);
    printf("recycled_buffer %d: %d elements read back as written\n", recycle, n);
    return 0;
}
