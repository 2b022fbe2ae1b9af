/* A test-only LD_PRELOAD shim against Oclgrind 21.10's recycled-buffer bug (recycled_buffer.c): every
 * buffer created on an Oclgrind context gets one extra reference, so that no release (the program's,
 * or Oclgrind's own when a command that used the buffer completes) frees it before the process
 * ends. Oclgrind then never hands a released buffer's index to a new buffer, and every buffer's
 * shadow memory is its own, allocated at its size. Buffers of other platforms are left alone.
 * Memory grows by every buffer the process creates on Oclgrind: fine for the small test frames.
 *
 * Why creation and not the last clReleaseMemObject: Oclgrind retains a kernel's buffers until its
 * command completes and releases them through its own internal entry (_clReleaseMemObject), which
 * no preloaded library sees; a program's release while a command is in flight would then not be
 * the last, and the buffer would still be freed. An extra reference taken at creation covers both.
 *
 * The program calls clCreateBuffer through the ICD loader (libOpenCL.so.1); this library, preloaded,
 * defines the symbol first and calls the loader's through dlsym(RTLD_NEXT). With
 * CLVIS_KEEP_BUFFERS_VERBOSE=1 it prints how many buffers it kept, at exit, to stderr. */
#define _GNU_SOURCE
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef cl_mem (*create_buffer_fn)(cl_context, cl_mem_flags, size_t, void*, cl_int*);

static create_buffer_fn next_create_buffer;
static pthread_once_t resolved = PTHREAD_ONCE_INIT;
static pthread_mutex_t kept_mutex = PTHREAD_MUTEX_INITIALIZER;
static unsigned long kept; /* buffers given their extra reference */

static void report_kept(void)
{
    fprintf(stderr, "keep_buffers: kept %lu Oclgrind buffers until exit\n", kept);
}

static void resolve(void)
{
    next_create_buffer = (create_buffer_fn)dlsym(RTLD_NEXT, "clCreateBuffer");
    if (!next_create_buffer) {
        fprintf(stderr, "keep_buffers: no clCreateBuffer after this library (is the program linked to OpenCL?)\n");
        abort();
    }
    const char* verbose = getenv("CLVIS_KEEP_BUFFERS_VERBOSE");
    if (verbose && !strcmp(verbose, "1")) atexit(report_kept);
}

/* Whether `context`'s first device belongs to the platform named Oclgrind. */
static int on_oclgrind(cl_context context)
{
    size_t bytes = 0;
    if (clGetContextInfo(context, CL_CONTEXT_DEVICES, 0, NULL, &bytes) != CL_SUCCESS || bytes < sizeof(cl_device_id))
        return 0;
    cl_device_id* devices = malloc(bytes);
    cl_platform_id platform = NULL;
    int found = devices && clGetContextInfo(context, CL_CONTEXT_DEVICES, bytes, devices, NULL) == CL_SUCCESS &&
                clGetDeviceInfo(devices[0], CL_DEVICE_PLATFORM, sizeof platform, &platform, NULL) == CL_SUCCESS;
    free(devices);
    char name[256] = "";
    return found && clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof name - 1, name, NULL) == CL_SUCCESS &&
           strstr(name, "Oclgrind") != NULL;
}

CL_API_ENTRY cl_mem CL_API_CALL clCreateBuffer(cl_context context, cl_mem_flags flags, size_t size, void* host_ptr,
                                               cl_int* errcode_ret)
{
    pthread_once(&resolved, resolve);
    cl_mem buffer = next_create_buffer(context, flags, size, host_ptr, errcode_ret);
    if (buffer && on_oclgrind(context) && clRetainMemObject(buffer) == CL_SUCCESS) {
        pthread_mutex_lock(&kept_mutex);
        ++kept;
        pthread_mutex_unlock(&kept_mutex);
    }
    return buffer;
}
