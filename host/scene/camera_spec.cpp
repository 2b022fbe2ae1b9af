// Camera descriptions (the tool's flags, scene files) into cameras: the one table of fields that
// both parse, their values checked by name, merging a file's description with flags, and the
// resolution against a scene's bounds and an image size.
#include <clvis/camera_spec.hpp>
#include <clvis/error.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <tuple>
#include <utility>

namespace clvis {

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& what)
{
    throw Error(Error::Kind::InvalidArgument, where + ": " + what);
}

std::string number(double v)
{
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

double positive(const CameraValue& v, std::size_t i, const std::string& where, const char* what)
{
    if (!(v.numbers[i] > 0)) bad(where, std::string(what) + " must be > 0, got " + number(v.numbers[i]));
    return v.numbers[i];
}

Vec3 vec3(const CameraValue& v) { return {v.numbers[0], v.numbers[1], v.numbers[2]}; }

using Setter = void (*)(CameraSpec&, const CameraValue&, const std::string& where);

struct FieldDef {
    CameraField field;
    Setter set;
};

/// The fields: a new one is a line here (and its use in CameraSpec::resolve).
const std::vector<FieldDef>& field_defs()
{
    static const std::vector<FieldDef> defs = {
        {{"eye", "X,Y,Z", "camera position (world units)", 3, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.eye = vec3(v); }},
        {{"target", "X,Y,Z", "point looked at", 3, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.target = vec3(v); }},
        {{"up", "X,Y,Z", "up vector (default 0,1,0)", 3, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.up = vec3(v); }},
        {{"fov", "DEGREES", "vertical field of view in degrees (perspective; default 45)", 1, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.fov = v.numbers[0]; }},
        {{"ortho", "[HEIGHT]", "orthographic camera of this view height (world units); bare: from the scene's bounds",
          1, true},
         [](CameraSpec& s, const CameraValue& v, const std::string& where) {
             s.ortho = true;
             s.ortho_height.reset();
             if (!v.bare) s.ortho_height = positive(v, 0, where, "the view height");
         }},
        {{"focal_length", "MM", "physical camera: focal length in mm", 1, false},
         [](CameraSpec& s, const CameraValue& v, const std::string& where) {
             s.focal_length = positive(v, 0, where, "the focal length");
         }},
        {{"film_gate", "W,H", "physical camera: film gate (aperture) in mm, e.g. 36,24", 2, false},
         [](CameraSpec& s, const CameraValue& v, const std::string& where) {
             s.film_gate = std::array<double, 2>{positive(v, 0, where, "the gate's width"),
                                                 positive(v, 1, where, "the gate's height")};
         }},
        {{"fit", "fill|overscan", "physical camera: the film gate fills the image, or all of it is inside (default fill)",
          0, false},
         [](CameraSpec& s, const CameraValue& v, const std::string& where) {
             try {
                 s.fit = film_fit_from_string(v.word);
             } catch (const Error&) {
                 bad(where, "expected fill or overscan, got '" + v.word + "'");
             }
         }},
        {{"intrinsics", "FX,FY,CX,CY", "focal lengths and principal point in pixels (pixel i's centre at i+0.5)", 4,
          false},
         [](CameraSpec& s, const CameraValue& v, const std::string& where) {
             s.intrinsics = Intrinsics{positive(v, 0, where, "fx"), positive(v, 1, where, "fy"), v.numbers[2],
                                       v.numbers[3]};
         }},
        {{"pose", "M", "camera-to-world 4x4 matrix, 16 numbers row by row (replaces eye, target and up)", 16, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) {
             Mat4 m;
             std::copy(v.numbers.begin(), v.numbers.end(), m.m.begin());
             s.pose = m;
         }},
        {{"near", "DEPTH", "near view depth (> 0)", 1, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.near = v.numbers[0]; }},
        {{"far", "DEPTH", "far view depth (> near)", 1, false},
         [](CameraSpec& s, const CameraValue& v, const std::string&) { s.far = v.numbers[0]; }},
    };
    return defs;
}

double parse_number(const std::string& text, const std::string& where)
{
    double v = 0;
    const char* end = text.data() + text.size();
    auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end) bad(where, "'" + text + "' is not a number");
    return v;
}

} // namespace

const std::vector<CameraField>& camera_fields()
{
    static const std::vector<CameraField> fields = [] {
        std::vector<CameraField> out;
        for (const FieldDef& d : field_defs()) out.push_back(d.field);
        return out;
    }();
    return fields;
}

void set_camera_field(CameraSpec& spec, const std::string& name, const CameraValue& value, const std::string& where)
{
    const FieldDef* def = nullptr;
    for (const FieldDef& d : field_defs())
        if (name == d.field.name) def = &d;
    if (!def) bad(where, "not a camera field");
    const CameraField& f = def->field;
    if (value.bare) {
        if (!f.bare) bad(where, std::string("needs a value (") + f.form + ")");
    } else if (f.numbers == 0) {
        if (!value.numbers.empty() || value.word.empty()) bad(where, std::string("expected ") + f.form);
    } else {
        if (!value.word.empty() || value.numbers.size() != std::size_t(f.numbers))
            bad(where, "expected " + std::to_string(f.numbers) + (f.numbers > 1 ? " numbers (" : " number (") +
                           f.form + ")");
        for (double v : value.numbers)
            if (!std::isfinite(v)) bad(where, number(v) + " is not finite");
    }
    def->set(spec, value, where);
}

void set_camera_field(CameraSpec& spec, const std::string& name, const std::string& text, const std::string& where)
{
    CameraValue value;
    const auto& fields = camera_fields();
    bool takes_word = false;
    for (const CameraField& f : fields)
        if (name == f.name) takes_word = f.numbers == 0;
    if (text.empty()) {
        value.bare = true;
    } else if (takes_word) {
        value.word = text;
    } else {
        std::size_t start = 0;
        while (true) {
            std::size_t comma = text.find(',', start);
            value.numbers.push_back(parse_number(text.substr(start, comma - start), where));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    }
    set_camera_field(spec, name, value, where);
}

bool CameraSpec::empty() const
{
    return !eye && !target && !up && !fov && !ortho && !focal_length && !film_gate && !fit && !near && !far &&
           !intrinsics && !pose;
}

CameraSpec CameraSpec::overridden_by(const CameraSpec& over) const
{
    CameraSpec r = *this;
    bool physical = over.focal_length || over.film_gate || over.fit;
    if (over.fov || over.ortho || physical || over.intrinsics) {
        r.fov.reset();
        r.ortho = false;
        r.ortho_height.reset();
        r.intrinsics.reset();
    }
    if (over.fov || over.ortho || over.intrinsics) {
        r.focal_length.reset();
        r.film_gate.reset();
        r.fit.reset();
    }
    if (over.pose) {
        r.eye.reset();
        r.target.reset();
        r.up.reset();
    }
    if (over.eye || over.target) r.pose.reset();
    auto take = [](auto& mine, const auto& theirs) {
        if (theirs) mine = theirs;
    };
    take(r.eye, over.eye);
    take(r.target, over.target);
    take(r.up, over.up);
    take(r.fov, over.fov);
    if (over.ortho) {
        r.ortho = true;
        r.ortho_height = over.ortho_height;
    }
    take(r.focal_length, over.focal_length);
    take(r.film_gate, over.film_gate);
    take(r.fit, over.fit);
    take(r.near, over.near);
    take(r.far, over.far);
    take(r.intrinsics, over.intrinsics);
    take(r.pose, over.pose);
    return r;
}

namespace {

/// The camera's own error ("camera: near must be ...") renamed to the field as the caller spells it.
[[noreturn]] void rename_camera_error(const Error& e, const std::function<std::string(const std::string&)>& name)
{
    std::string msg = e.what();
    const std::string prefix = "camera: ";
    if (msg.rfind(prefix, 0) == 0) {
        std::string rest = msg.substr(prefix.size());
        for (auto [words, field] : {std::pair{"eye", "eye"}, {"target", "target"}, {"up", "up"}, {"near", "near"},
                                    {"far", "far"}, {"fov", "fov"}, {"ortho height", "ortho"},
                                    {"focal length", "focal_length"}, {"film gate", "film_gate"},
                                    {"intrinsics", "intrinsics"}, {"pose", "pose"}})
            if (rest.rfind(words, 0) == 0) bad(name(field), rest);
    }
    throw e;
}

/// The depth range of the framing camera for an eye at `eye` (CONVENTIONS.md), kept positive.
std::pair<double, double> framing_depths(const Bounds& b, Vec3 eye)
{
    if (b.empty() || !is_finite(b.lo) || !is_finite(b.hi)) return {Camera{}.near, Camera{}.far};
    double dist = length(b.center() - eye), radius = length(b.extent()) / 2;
    double near = std::fmax(0.9 * (dist - radius), 1e-4 * std::fmax(dist + radius, 1e-30));
    double far = 1.1 * (dist + radius);
    return {near, far > near ? far : near * 2};
}

} // namespace

Camera CameraSpec::resolve(const Bounds& b, int width, int height,
                           const std::function<std::string(const std::string&)>& name_of) const
{
    auto name = [&](const std::string& field) { return name_of ? name_of(field) : field; };
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "camera: image size must be positive, got " +
                                                      std::to_string(width) + "x" + std::to_string(height));
    bool physical = focal_length || film_gate || fit;
    if (fov && ortho) bad(name("fov"), "give one projection: " + name("fov") + " or " + name("ortho") + ", not both");
    if (physical && (fov || ortho))
        bad(name("focal_length"), "the physical camera replaces " + name(fov ? "fov" : "ortho") + ": give one");
    if (fit && !focal_length && !film_gate)
        bad(name("fit"), "applies to the physical camera only: give " + name("focal_length") + " and " +
                             name("film_gate") + " too");
    if (physical && !focal_length) bad(name("focal_length"), "is needed with " + name("film_gate"));
    if (physical && !film_gate) bad(name("film_gate"), "is needed with " + name("focal_length"));
    if (intrinsics && (fov || ortho || physical))
        bad(name("intrinsics"), "replaces " + name(fov ? "fov" : ortho ? "ortho" : "focal_length") + ": give one");
    if (pose && (eye || target || up))
        bad(name("pose"), "replaces " + name(eye ? "eye" : target ? "target" : "up") + ": give one");
    if (eye && !target) bad(name("target"), "is needed with " + name("eye"));
    if (target && !eye) bad(name("eye"), "is needed with " + name("target"));

    try {
        Camera cam;
        if (framing()) {
            cam = Camera::framing(b, ortho ? Projection::Orthographic : Projection::Perspective);
        } else if (pose) {
            cam = Camera::from_pose(*pose);
            std::tie(cam.near, cam.far) = framing_depths(b, cam.eye);
        } else {
            cam.eye = *eye;
            cam.target = *target;
            std::tie(cam.near, cam.far) = framing_depths(b, cam.eye);
        }
        if (up) cam.up = *up;
        if (fov) {
            cam.projection = Projection::Perspective;
            cam.fov_y = *fov;
        }
        if (ortho) {
            cam.projection = Projection::Orthographic;
            if (ortho_height) cam.ortho_height = *ortho_height;
            else if (!framing()) cam.ortho_height = length(b.extent());
        }
        if (intrinsics) {
            cam.projection = Projection::Perspective;
            cam.intrinsics = *intrinsics;
        }
        if (near) cam.near = *near;
        if (far) cam.far = *far;
        if (physical)
            cam = Camera::physical(cam.eye, cam.target, cam.up, *focal_length, (*film_gate)[0], (*film_gate)[1],
                                   fit.value_or(FilmFit::Fill), double(width) / height, cam.near, cam.far);
        cam.validate();
        return cam;
    } catch (const Error& e) {
        rename_camera_error(e, name);
    }
}

} // namespace clvis
