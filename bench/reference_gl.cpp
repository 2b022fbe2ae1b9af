// Mesa/llvmpipe reference through EGL without a window: a GL 3.3 core context on the surfaceless
// platform, the scene in one vertex and one index buffer, drawn by one glDrawElements into an
// R32UI + DEPTH_COMPONENT32F framebuffer object. GL's row 0 is the bottom: rows are flipped on
// read-back. Pixel centres agree: GL samples window (i + .5, j + .5), and window row j is raster
// row height - 1 - j.
#include "reference_gl.hpp"

#include <stdexcept>

#if CLVIS_HAVE_GL

#define EGL_EGLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <vector>

namespace clvis::bench {

namespace {

const char* vertex_shader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 clip_from_world;
void main() { gl_Position = clip_from_world * vec4(position, 1.0); }
)";

// gl_PrimitiveID counts the triangles of the draw from 0: triangles are drawn in id order.
const char* fragment_shader = R"(#version 330 core
layout(location = 0) out uint id;
void main() { id = uint(gl_PrimitiveID); }
)";

std::string hex(unsigned v)
{
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%04X", v);
    return buf;
}

[[noreturn]] void fail_egl(const char* call)
{
    throw std::runtime_error(std::string("gl: ") + call + " failed (EGL error " + hex(unsigned(eglGetError())) + ")");
}

void check_gl(const char* what)
{
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) throw std::runtime_error(std::string("gl: ") + what + ": GL error " + hex(e));
}

/// Mesa reads LP_NUM_THREADS when the display is first initialised: one display per process,
/// initialised once and kept (eglTerminate would pull it from under other references).
EGLDisplay surfaceless_display(int threads)
{
    static std::mutex mutex;
    static EGLDisplay display = EGL_NO_DISPLAY;
    std::lock_guard<std::mutex> lock(mutex);
    if (display != EGL_NO_DISPLAY) return display;
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d == EGL_NO_DISPLAY) fail_egl("eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) fail_egl("eglInitialize");
    display = d;
    return display;
}

GLuint compile(GLenum type, const char* source)
{
    GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw std::runtime_error(std::string("gl: shader compile failed: ") + log);
    }
    return shader;
}

/// View depth from a window depth in [0, 1] (glDepthRange 0..1, NDC z from -1 at near to +1 at far).
float view_depth(const Camera& camera, float window_z)
{
    double z = 2.0 * window_z - 1.0, n = camera.near, f = camera.far;
    if (camera.projection == Projection::Orthographic) return float(n + (z + 1) / 2 * (f - n));
    return float(2 * f * n / ((f + n) - z * (f - n)));
}

} // namespace

struct GlReference::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    GLuint program = 0, vao = 0, vbo = 0, ibo = 0;
    GLint clip_from_world = -1;
    GLsizei index_count = 0;
    std::string description;

    void make_current() const
    {
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) fail_egl("eglMakeCurrent");
    }

    ~Impl()
    {
        if (context == EGL_NO_CONTEXT) return;
        if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
            if (program) glDeleteProgram(program);
            if (vbo) glDeleteBuffers(1, &vbo);
            if (ibo) glDeleteBuffers(1, &ibo);
            if (vao) glDeleteVertexArrays(1, &vao);
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(display, context);
    }
};

GlReference::GlReference(const Scene& scene, int threads) : impl_(std::make_unique<Impl>())
{
    if (threads < 1) throw std::runtime_error("gl: threads must be >= 1");
    if (scene.empty()) throw std::runtime_error("gl: the scene holds no triangles");
    if (scene.triangle_count() * 3 > std::size_t(std::numeric_limits<GLsizei>::max()))
        throw std::runtime_error("gl: too many triangles for one glDrawElements");
    Impl& g = *impl_;
    g.display = surfaceless_display(threads);
    if (!eglBindAPI(EGL_OPENGL_API)) fail_egl("eglBindAPI(EGL_OPENGL_API)");
    // No window: a pbuffer-capable config (EGL's default asks for EGL_WINDOW_BIT); drawing goes to
    // a framebuffer object, so its colour format does not matter.
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(g.display, config_attribs, &config, 1, &configs) || configs < 1)
        fail_egl("eglChooseConfig(EGL_OPENGL_BIT)");
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    g.context = eglCreateContext(g.display, config, EGL_NO_CONTEXT, context_attribs);
    if (g.context == EGL_NO_CONTEXT) fail_egl("eglCreateContext(OpenGL 3.3 core)");
    g.make_current();
    g.description = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + "; " +
                    reinterpret_cast<const char*>(glGetString(GL_VERSION));

    GLuint vs = compile(GL_VERTEX_SHADER, vertex_shader);
    GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_shader);
    g.program = glCreateProgram();
    glAttachShader(g.program, vs);
    glAttachShader(g.program, fs);
    glLinkProgram(g.program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = 0;
    glGetProgramiv(g.program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[2048] = {};
        glGetProgramInfoLog(g.program, sizeof log, nullptr, log);
        throw std::runtime_error(std::string("gl: program link failed: ") + log);
    }
    g.clip_from_world = glGetUniformLocation(g.program, "clip_from_world");

    const std::vector<float>& positions = scene.world_positions();
    const std::vector<std::uint32_t>& indices = scene.world_indices();
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    glGenBuffers(1, &g.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(positions.size() * sizeof(float)), positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glEnableVertexAttribArray(0);
    glGenBuffers(1, &g.ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    g.index_count = GLsizei(indices.size());
    check_gl("uploading the scene");
}

GlReference::~GlReference() = default;

std::string GlReference::description() const { return impl_->description; }

/// One camera in a framebuffer object of the view's size: R32UI ids and 32-bit float depth.
class GlReference::View final : public ReferenceView {
public:
    View(const GlReference::Impl& ref, const Camera& c, int width, int height) : g(ref), camera(c)
    {
        result_.name = "llvmpipe";
        result_.width = width;
        result_.height = height;
        g.make_current();
        try {
            make_framebuffer();
            set_up_frame();
            draw(); // warm-up: the first draw compiles the shaders for the rasterizer
            check_gl("the warm-up frame");
        } catch (...) {
            release();
            throw;
        }
    }

    const ReferenceResult& result() override
    {
        g.make_current();
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        check_gl("drawing");
        read_back();
        return result_;
    }

    ~View() override { release(); }

private:
    const GlReference::Impl& g;
    Camera camera;
    GLuint fbo = 0, colour = 0, depth = 0;

    void before_frame() override
    {
        g.make_current();
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        set_up_frame();
    }

    void render_frame() override { draw(); }

    void release()
    {
        if (!eglMakeCurrent(g.display, EGL_NO_SURFACE, EGL_NO_SURFACE, g.context)) return;
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (colour) glDeleteRenderbuffers(1, &colour);
        if (depth) glDeleteRenderbuffers(1, &depth);
        fbo = colour = depth = 0;
    }

    void make_framebuffer()
    {
        GLint max_size = 0;
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
        if (result_.width > max_size || result_.height > max_size)
            throw std::runtime_error("gl: " + std::to_string(result_.width) + "x" + std::to_string(result_.height) +
                                     " exceeds GL_MAX_RENDERBUFFER_SIZE " + std::to_string(max_size));
        glGenRenderbuffers(1, &colour);
        glBindRenderbuffer(GL_RENDERBUFFER, colour);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, result_.width, result_.height);
        glGenRenderbuffers(1, &depth);
        glBindRenderbuffer(GL_RENDERBUFFER, depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, result_.width, result_.height);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("gl: framebuffer incomplete: " + hex(status));
    }

    /// The program, the camera's matrix and the fixed-function state of every frame.
    void set_up_frame()
    {
        // Camera matrices are row-major (p' = M p): transpose on upload.
        Mat4 m = camera.projection_matrix(result_.width, result_.height) * camera.view_matrix();
        float clip_from_world[16];
        for (int k = 0; k < 16; ++k) clip_from_world[k] = float(m.m[k]);
        glUseProgram(g.program);
        glUniformMatrix4fv(g.clip_from_world, 1, GL_TRUE, clip_from_world);
        glBindVertexArray(g.vao);
        glViewport(0, 0, result_.width, result_.height);
        glDisable(GL_CULL_FACE);
        glDisable(GL_BLEND);
        glDisable(GL_DITHER);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS); // an exact depth tie keeps the earlier, lower id
        glDepthMask(GL_TRUE);
        glDepthRange(0.0, 1.0);
        check_gl("setting up the frame");
    }

    void draw() const
    {
        const GLuint clear_id[4] = {background_id, 0, 0, 0};
        const GLfloat clear_depth = 1.0f;
        glClearBufferuiv(GL_COLOR, 0, clear_id);
        glClearBufferfv(GL_DEPTH, 0, &clear_depth);
        glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
        glFinish();
    }

    /// Ids flipped to row 0 on top; depth as view depth.
    void read_back()
    {
        const int width = result_.width, height = result_.height;
        std::size_t pixels = std::size_t(width) * height;
        std::vector<std::uint32_t> ids(pixels);
        std::vector<float> window_z(pixels);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, width, height, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
        glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, window_z.data());
        check_gl("glReadPixels");
        result_.ids.resize(pixels);
        result_.depth.resize(pixels);
        for (int j = 0; j < height; ++j) {
            std::size_t from = std::size_t(height - 1 - j) * width, to = std::size_t(j) * width;
            for (int i = 0; i < width; ++i) {
                std::uint32_t id = ids[from + i];
                result_.ids[to + i] = id;
                result_.depth[to + i] = id == background_id ? std::numeric_limits<float>::infinity()
                                                           : view_depth(camera, window_z[from + i]);
            }
        }
    }
};

std::unique_ptr<ReferenceView> GlReference::view(const Camera& camera, int width, int height)
{
    if (width <= 0 || height <= 0) throw std::runtime_error("gl: image size must be positive");
    camera.validate();
    return std::make_unique<View>(*impl_, camera, width, height);
}

ReferenceResult GlReference::render(const Camera& camera, int width, int height, int repeats, double budget_ms)
{
    std::unique_ptr<ReferenceView> v = view(camera, width, height);
    std::vector<double> ms;
    while (!enough_frames(ms, repeats, budget_ms)) ms.push_back(v->frame());
    return v->result();
}

bool gl_available() noexcept { return true; }

} // namespace clvis::bench

#else // !CLVIS_HAVE_GL

// A deliberate twin of reference_embree.cpp's: each reference ends in the same pair, available() and a stub
// that reports it was not built, so the driver treats every reference alike.

namespace clvis::bench {

constexpr const char* not_built = "gl: clvis was built without EGL and OpenGL (Debian: libegl-dev, libopengl-dev)";

struct GlReference::Impl {};

GlReference::GlReference(const Scene&, int) { throw std::runtime_error(not_built); }
GlReference::~GlReference() = default;
std::string GlReference::description() const { return "OpenGL (not built)"; }
ReferenceResult GlReference::render(const Camera&, int, int, int, double) { throw std::runtime_error(not_built); }
std::unique_ptr<ReferenceView> GlReference::view(const Camera&, int, int) { throw std::runtime_error(not_built); }
bool gl_available() noexcept { return false; }

} // namespace clvis::bench

#endif

namespace clvis::bench {

ReferenceResult render_gl(const Scene& scene, const Camera& camera, int width, int height, int repeats, int threads)
{
    try {
        GlReference reference(scene, threads);
        return reference.render(camera, width, height, repeats);
    } catch (const std::exception& e) {
        ReferenceResult failed;
        failed.name = "llvmpipe";
        failed.width = width;
        failed.height = height;
        failed.error = e.what();
        return failed;
    }
}

} // namespace clvis::bench
