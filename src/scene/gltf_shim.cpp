// gltf_shim.cpp: the only C++ file of fovsim and the only user of tinygltf (see gltf_shim.h).
//
// tinygltf parses the JSON, loads the buffers and decodes the images (stb_image). Everything after
// that is ours: extension policy, bounds checks of every accessor and index, flattening of the node
// hierarchy into asset space, and conversion to the plain C structs of scene.h.
//
// Errors travel as a C++ exception (load_error) up to gltf_load, which is the only place that
// prints and the only place a C++ exception may leave: nothing is thrown across the C boundary.
//
// Sections: >>util >>io >>extensions >>accessors >>images >>materials >>primitives >>nodes >>entry

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <string>
#include <vector>

#include <fcntl.h>
#include <zlib.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/config.h"
#include "core/file_read.h"
#include "core/fmath.h"
#include "core/log.h"
#include "core/status.h"
#include "scene/gltf_shim.h"
#include "scene/scene.h"

namespace {

// >>util

struct load_error {
    fs_status status;
    std::string msg; // "<where>: <what>", without the path
};

std::string strf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
std::string strf(const char *fmt, ...)
{
    char small[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0)
        return std::string(fmt);
    if ((size_t)n < sizeof small)
        return std::string(small, (size_t)n);
    std::string big((size_t)n + 1, '\0');
    va_start(ap, fmt);
    vsnprintf(&big[0], big.size(), fmt, ap);
    va_end(ap);
    big.resize((size_t)n);
    return big;
}

[[noreturn]] void fail(const std::string &msg, fs_status s = FS_ERR_ASSET)
{
    throw load_error{s, msg};
}

// First non-empty line of a (tinygltf) message, without trailing blanks: log lines are one line.
std::string first_line(const std::string &s)
{
    size_t b = 0;
    while (b < s.size()) {
        size_t e = s.find_first_of("\r\n", b);
        if (e == std::string::npos)
            e = s.size();
        std::string line = s.substr(b, e - b);
        while (!line.empty() && (line.back() == ' ' || line.back() == '\t'))
            line.pop_back();
        if (!line.empty())
            return line;
        b = e + 1;
    }
    return std::string();
}

// Input quoted in a message, as every message quotes it (log_quote): at most 250 bytes.
std::string quote(const std::string &s)
{
    char buf[256];
    return log_quote(buf, sizeof buf, s.data(), s.size());
}

void copy_name(char *dst, size_t cap, const std::string &src)
{
    size_t n = std::min(src.size(), cap - 1);
    memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

bool ends_with_ci(const std::string &s, const char *suffix)
{
    size_t n = strlen(suffix);
    if (s.size() < n)
        return false;
    for (size_t i = 0; i < n; i++) {
        unsigned char a = (unsigned char)s[s.size() - n + i], b = (unsigned char)suffix[i];
        if (tolower(a) != tolower(b))
            return false;
    }
    return true;
}

std::string base_name(const std::string &path)
{
    size_t k = path.find_last_of('/');
    return k == std::string::npos ? path : path.substr(k + 1);
}

// off + len <= total, without overflow.
bool fits(size_t off, size_t len, size_t total) { return off <= total && len <= total - off; }

// malloc'd copy of a vector, for the C structs (freed by asset_free). Throws bad_alloc.
template <class T> T *c_copy(const std::vector<T> &v)
{
    if (v.empty())
        return nullptr;
    T *p = static_cast<T *>(malloc(v.size() * sizeof(T)));
    if (!p)
        throw std::bad_alloc();
    memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

// Everything the C asset will own, held here until the load succeeds; freed if it does not.
struct builder {
    std::vector<prim> prims;
    std::vector<material> materials;
    std::vector<image_rgba8> images;

    builder() = default;
    builder(const builder &) = delete;
    builder &operator=(const builder &) = delete;
    ~builder()
    {
        for (prim &p : prims) {
            free(p.positions);
            free(p.normals);
            free(p.uvs);
            free(p.colors);
            free(p.indices);
        }
        for (image_rgba8 &im : images)
            free(im.rgba);
    }
};

// >>io

// The whole of a regular file of at most MAX_ASSET_FILE_BYTES; anything else is refused by what it
// is before it is opened (file_open_regular: a FIFO would hang, a device never end).
std::vector<unsigned char> read_file(const std::string &path)
{
    struct stat sb;
    const char *why = "";
    int fd = file_open_regular(path.c_str(), &sb, &why);
    if (fd < 0) {
        if (errno == ENOENT || errno == EACCES || errno == ENOTDIR || errno == ELOOP || errno == ENAMETOOLONG)
            fail(strf("cannot open: %s", why), FS_ERR_IO);
        fail(strf("%s; expected a glTF file", why));
    }
    if ((unsigned long long)sb.st_size > (unsigned long long)MAX_ASSET_FILE_BYTES) {
        close(fd);
        fail(strf("is larger than %llu MiB (MAX_ASSET_FILE_BYTES)", (unsigned long long)MAX_ASSET_FILE_BYTES >> 20));
    }
    std::vector<unsigned char> data;
    unsigned char chunk[1 << 16];
    for (;;) {
        ssize_t n = read(fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            int err = errno;
            close(fd);
            fail(strf("cannot read: %s", strerror(err)), FS_ERR_IO);
        }
        if (n == 0)
            break;
        data.insert(data.end(), chunk, chunk + n);
        if (data.size() > (size_t)MAX_ASSET_FILE_BYTES) { // grew while read
            close(fd);
            fail(strf("is larger than %llu MiB (MAX_ASSET_FILE_BYTES)",
                      (unsigned long long)MAX_ASSET_FILE_BYTES >> 20));
        }
    }
    close(fd);
    return data;
}

// Refuses JSON text nested deeper than MAX_GLTF_JSON_DEPTH arrays and objects before tinygltf sees
// it: its parser recurses per level and overflows the stack on deep input. Brackets inside strings
// do not count; anything else malformed is left to the parser. `base` is the text's offset in the
// file, for the message.
void check_json_depth(const unsigned char *s, size_t n, size_t base)
{
    int depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < n; i++) {
        const unsigned char c = s[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > MAX_GLTF_JSON_DEPTH)
                fail(strf("JSON nested deeper than %d arrays and objects (at byte %zu); expected a glTF document",
                          MAX_GLTF_JSON_DEPTH, base + i));
        } else if ((c == ']' || c == '}') && depth > 0) {
            depth--;
        }
    }
}


// The glTF properties whose values are indices, counts, offsets or enums: a non-negative integer
// that fits an int. tinygltf reads a value of the wrong kind as "absent" (an accessor byteOffset of
// -8 became 0) and casts one too large to int ("mesh": 2^40 became mesh 0); the rule is that
// such a file be refused, naming the JSON path. Objects under "extras" are the author's own data
// and are not looked at.
bool is_index_key(const std::string &k)
{
    static const char *const keys[] = {"byteOffset", "byteLength", "byteStride", "count",     "buffer",  "bufferView",
                                       "mesh",       "skin",       "camera",     "material",  "indices", "sampler",
                                       "source",     "texCoord",   "index",      "node",      "input",   "output",
                                       "scene",      "componentType", "mode",   "target",    "magFilter", "minFilter",
                                       "wrapS",      "wrapT",      "skeleton"};
    for (const char *c : keys)
        if (k == c)
            return true;
    return false;
}

// Arrays whose elements are indices.
bool is_index_array_key(const std::string &k)
{
    return k == "children" || k == "nodes" || k == "joints";
}

void check_index_value(const nlohmann::json &v, const std::string &where)
{
    const bool ok = (v.is_number_unsigned() && v.get<uint64_t>() <= (uint64_t)INT_MAX) ||
                    (v.is_number_integer() && v.get<int64_t>() >= 0 && v.get<int64_t>() <= INT_MAX);
    if (!ok) {
        std::string shown = v.dump();
        if (shown.size() > 40)
            shown = shown.substr(0, 40) + "...";
        fail(strf("%s: expected an integer 0..%d, got %s", where.c_str(), INT_MAX, shown.c_str()));
    }
}

void check_json_values(const nlohmann::json &j, const std::string &where, int depth)
{
    if (depth > MAX_GLTF_JSON_DEPTH)
        return; // check_json_depth has refused it already
    if (j.is_array())
        for (size_t i = 0; i < j.size(); i++)
            check_json_values(j[i], strf("%s[%zu]", where.c_str(), i), depth + 1);
    if (!j.is_object())
        return;
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string &k = it.key();
        const nlohmann::json &v = it.value();
        const std::string at = where.empty() ? k : where + "." + k;
        if (k == "extras")
            continue;
        if (k == "attributes" && v.is_object()) // a primitive's: attribute names to accessor indices
            for (auto a = v.begin(); a != v.end(); ++a)
                check_index_value(a.value(), at + "." + a.key());
        else if (is_index_key(k) && !v.is_structured()) // (an animation channel's "target" is an object)
            check_index_value(v, at);
        else if (is_index_array_key(k) && v.is_array())
            // a scene's "nodes" are indices; the document's "nodes" are node objects
            for (size_t i = 0; i < v.size(); i++) {
                if (v[i].is_structured())
                    check_json_values(v[i], strf("%s[%zu]", at.c_str(), i), depth + 2);
                else
                    check_index_value(v[i], strf("%s[%zu]", at.c_str(), i));
            }
        else
            check_json_values(v, at, depth + 1);
    }
}

// The document's indices, counts and offsets (check_json_values); a document that is not JSON is
// left to tinygltf, which says where.
void check_json_indices(const unsigned char *s, size_t n)
{
    const nlohmann::json j = nlohmann::json::parse(s, s + n, nullptr, false);
    if (!j.is_discarded())
        check_json_values(j, "", 0);
}

// >>uris
//
// The rule (README "Limits"): a buffer or image URI names a regular file under the folder of the
// glTF file that references it (after resolving symbolic links), or under --asset-root DIR when one
// is given; data: URIs are decoded in memory. A URI that leaves the folder is refused before the file
// system is touched when it does so by its `..` components, and after realpath when by a link. A
// directory, device or FIFO is refused by what it is, and a file larger than MAX_ASSET_FILE_BYTES by
// its size; messages quote the URI, never the size or content of a file outside the folder. tinygltf
// reaches the file system only through these callbacks.

std::string g_asset_root; // realpath of --asset-root, or empty
uint64_t g_image_budget = GLTF_DEFAULT_IMAGE_PIXELS, g_scene_budget = GLTF_DEFAULT_SCENE_PIXELS;
uint64_t g_scene_pixels; // declared pixels decoded since gltf_begin_scene

struct uri_state {
    std::string base_dir;  // as passed to tinygltf ("" = the current directory)
    std::string root;      // realpath of base_dir
    std::map<std::string, std::string> refusals; // candidate path -> why it was refused
    std::string last;      // the last refusal, for a failed buffer
};

bool path_under(const std::string &p, const std::string &root)
{
    if (root.empty())
        return false;
    if (root == "/")
        return true;
    return p.size() > root.size() && p.compare(0, root.size(), root) == 0 && p[root.size()] == '/';
}

// The URI part of a candidate path tinygltf built with JoinPath(base_dir, uri); empty when the
// candidate is not below base_dir (its fallback to the current directory).
bool uri_of(const uri_state &u, const std::string &path, std::string *uri)
{
    if (u.base_dir.empty()) {
        *uri = path.compare(0, 2, "./") == 0 ? path.substr(2) : path;
        return true;
    }
    const std::string pre = u.base_dir.back() == '/' ? u.base_dir : u.base_dir + "/";
    if (path.compare(0, pre.size(), pre) != 0)
        return false;
    *uri = path.substr(pre.size());
    return true;
}

// True when the `..` components of a relative path climb above its start.
bool climbs_out(const std::string &rel)
{
    int depth = 0;
    size_t b = 0;
    while (b <= rel.size()) {
        size_t e = rel.find('/', b);
        if (e == std::string::npos)
            e = rel.size();
        const std::string c = rel.substr(b, e - b);
        if (c == "..") {
            if (--depth < 0)
                return true;
        } else if (!c.empty() && c != ".") {
            depth++;
        }
        b = e + 1;
    }
    return false;
}

// Checks `path` against the rule; on refusal records why (keyed by the path) and returns false.
bool uri_allowed(uri_state &u, const std::string &path)
{
    std::string uri;
    if (!uri_of(u, path, &uri))
        return false; // tinygltf's second guess, the current directory: never
    auto refuse = [&](const std::string &why) {
        u.last = strf("URI %s %s", quote(uri).c_str(), why.c_str());
        u.refusals[path] = u.last;
        return false;
    };
    const std::string where = g_asset_root.empty() ? "the glTF file's folder"
                                                   : "the glTF file's folder or --asset-root";
    if (!uri.empty() && uri[0] == '/')
        return refuse("is an absolute path, expected a path relative to the glTF file");
    if (g_asset_root.empty() && climbs_out(uri))
        return refuse("leaves " + where + " (URIs name files under it; --asset-root DIR widens that)");
    char real[PATH_MAX];
    if (!realpath(path.c_str(), real))
        return refuse(strf("cannot be opened: %s", strerror(errno)));
    if (!path_under(real, u.root) && !path_under(real, g_asset_root))
        return refuse("leaves " + where + " (URIs name files under it; --asset-root DIR widens that)");
    struct stat sb;
    if (stat(real, &sb) != 0)
        return refuse(strf("cannot be opened: %s", strerror(errno)));
    if (S_ISDIR(sb.st_mode))
        return refuse("is a directory, expected a file");
    if (!S_ISREG(sb.st_mode))
        return refuse("is not a regular file (a device, FIFO or socket), expected a file");
    if ((unsigned long long)sb.st_size > (unsigned long long)MAX_ASSET_FILE_BYTES)
        return refuse(strf("is larger than %llu MiB (MAX_ASSET_FILE_BYTES)",
                           (unsigned long long)MAX_ASSET_FILE_BYTES >> 20));
    return true;
}

bool fs_file_exists(const std::string &path, void *user)
{
    return uri_allowed(*static_cast<uri_state *>(user), path);
}

std::string fs_expand(const std::string &path, void *) { return path; } // no ~ or $VAR expansion

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    uri_state &u = *static_cast<uri_state *>(user);
    if (!uri_allowed(u, path)) { // checked again: FileExists may not have been asked
        if (err)
            *err += u.last + "\n";
        return false;
    }
    struct stat sb;
    const char *why = "";
    int fd = file_open_regular(path.c_str(), &sb, &why); // uri_allowed checked the path; this the file
    if (fd < 0 || (unsigned long long)sb.st_size > (unsigned long long)MAX_ASSET_FILE_BYTES) {
        if (fd >= 0)
            close(fd);
        std::string uri;
        uri_of(u, path, &uri);
        u.last = strf("URI %s cannot be read as a file", quote(uri).c_str());
        if (err)
            *err += u.last + "\n";
        return false;
    }
    out->resize((size_t)sb.st_size);
    size_t got = 0;
    while (got < out->size()) {
        ssize_t n = read(fd, out->data() + got, out->size() - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        got += (size_t)n;
    }
    close(fd);
    if (got != out->size()) {
        std::string uri;
        uri_of(u, path, &uri);
        u.last = strf("URI %s could not be read completely", quote(uri).c_str());
        if (err)
            *err += u.last + "\n";
        return false;
    }
    return true;
}

bool fs_write(std::string *err, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (err)
        *err += "fovsim does not write glTF files\n";
    return false;
}

// >>extensions

// Extensions that change how geometry or textures are decoded: data we would read wrongly or not
// at all, so an asset that merely uses them is refused too.
const char *const k_decoding_extensions[] = {
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_meshopt_compression",
    "KHR_texture_basisu",         "EXT_texture_webp",        "EXT_texture_avif",
    "MSFT_texture_dds",
};
// Required extensions fovsim does honour: quantized attributes are read through the generic
// accessor path (any component type, normalized flag respected).
const char *const k_honoured_extensions[] = {"KHR_mesh_quantization"};

template <size_t N> bool in_list(const std::string &name, const char *const (&list)[N])
{
    for (const char *s : list)
        if (name == s)
            return true;
    return false;
}

void check_extension_map(const tinygltf::ExtensionMap &m)
{
    for (const auto &kv : m)
        if (in_list(kv.first, k_decoding_extensions))
            fail(strf("uses extension %s, which fovsim does not support", kv.first.c_str()));
}

// Runs even when tinygltf failed: it fills the extension lists before it touches buffers, so a
// meshopt or KTX2 file is refused by name instead of with a confusing buffer or image error.
void check_extensions(const char *path, const tinygltf::Model &m, bool full)
{
    for (const std::string &e : m.extensionsRequired)
        if (!in_list(e, k_honoured_extensions))
            fail(strf("requires extension %s, which fovsim does not support", e.c_str()));
    std::string ignored;
    for (const std::string &e : m.extensionsUsed) {
        if (in_list(e, k_decoding_extensions))
            fail(strf("uses extension %s, which fovsim does not support", e.c_str()));
        if (!in_list(e, k_honoured_extensions))
            ignored += (ignored.empty() ? "" : ", ") + e;
    }
    if (!full)
        return;
    // Files that use a decoding extension without declaring it.
    for (const tinygltf::Mesh &mesh : m.meshes)
        for (const tinygltf::Primitive &p : mesh.primitives)
            check_extension_map(p.extensions);
    for (const tinygltf::BufferView &bv : m.bufferViews)
        check_extension_map(bv.extensions);
    for (const tinygltf::Texture &t : m.textures)
        check_extension_map(t.extensions);
    if (!ignored.empty())
        log_warn("%s: ignoring extension(s) %s (not required, not implemented by fovsim)", path,
                 ignored.c_str());
}

// >>accessors

double decode_component(const unsigned char *p, int ctype, bool normalized)
{
    switch (ctype) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    default:
        return 0.0;
    }
}

bool valid_component_type(int ctype)
{
    switch (ctype) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return true;
    default:
        return false; // INT and DOUBLE are not glTF 2.0 accessor types
    }
}

const char *type_name(int t)
{
    switch (t) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "(unknown)";
    }
}

// The bytes of bufferView `bvi`, checked against its buffer.
const unsigned char *view_bytes(const tinygltf::Model &m, int bvi, size_t *len)
{
    if (bvi < 0 || (size_t)bvi >= m.bufferViews.size())
        fail(strf("bufferView %d does not exist (the file has %zu)", bvi, m.bufferViews.size()));
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)bvi];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        fail(strf("bufferViews[%d]: buffer %d does not exist (the file has %zu)", bvi, bv.buffer,
                  m.buffers.size()));
    const std::vector<unsigned char> &buf = m.buffers[(size_t)bv.buffer].data;
    if (!fits(bv.byteOffset, bv.byteLength, buf.size()))
        fail(strf("bufferViews[%d]: byteOffset + byteLength exceeds buffer %d (size %zu)", bvi,
                  bv.buffer, buf.size()));
    *len = bv.byteLength;
    return buf.data() + bv.byteOffset;
}

// Most elements one accessor may have (guards allocations for accessors without a bufferView,
// whose count is not bounded by any data).
const size_t k_max_accessor_count = (size_t)1 << 26;

// Reads accessor `ai` as doubles (count * components; doubles hold every uint32 index exactly),
// with byteStride, byteOffset, normalized and sparse substitution applied. Checks every byte
// range. `types` lists the accepted accessor types (TINYGLTF_TYPE_*), 0-terminated.
std::vector<double> read_accessor(const tinygltf::Model &m, int ai, const char *what,
                                  const int *types, int *comps_out)
{
    if (ai < 0 || (size_t)ai >= m.accessors.size())
        fail(strf("%s: accessor %d does not exist (the file has %zu)", what, ai, m.accessors.size()));
    const tinygltf::Accessor &a = m.accessors[(size_t)ai];
    bool type_ok = false;
    for (const int *t = types; *t; t++)
        type_ok = type_ok || a.type == *t;
    if (!type_ok)
        fail(strf("accessors[%d]: type %s is not valid for %s", ai, type_name(a.type), what));
    if (!valid_component_type(a.componentType))
        fail(strf("accessors[%d]: componentType %d is not a glTF component type", ai, a.componentType));
    const int comps = tinygltf::GetNumComponentsInType((uint32_t)a.type);
    const size_t csize = (size_t)tinygltf::GetComponentSizeInBytes((uint32_t)a.componentType);
    const size_t elem = (size_t)comps * csize;
    const size_t count = a.count;
    if (count > k_max_accessor_count)
        fail(strf("accessors[%d]: count %zu is more than fovsim accepts (%zu)", ai, count,
                  k_max_accessor_count));

    const unsigned char *base = nullptr;
    size_t stride = elem;
    if (a.bufferView >= 0) {
        size_t len = 0;
        base = view_bytes(m, a.bufferView, &len);
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
        if (bv.byteStride != 0) {
            if (bv.byteStride < elem)
                fail(strf("accessors[%d]: byteStride %zu of bufferView %d is smaller than one element "
                          "(%zu bytes)",
                          ai, bv.byteStride, a.bufferView, elem));
            stride = bv.byteStride;
        }
        // The last element ends at byteOffset + (count-1)*stride + elem; stride <= 252 and
        // count <= 2^26, so this cannot overflow.
        size_t need = count ? (count - 1) * stride + elem : 0;
        if (!fits(a.byteOffset, need, len))
            fail(strf("accessors[%d]: byteOffset + count*stride exceeds bufferView %d (size %zu)", ai,
                      a.bufferView, len));
        base += a.byteOffset;
    }

    // Without a bufferView the accessor is all zeros (glTF 2.0 spec, "Accessors") and its count
    // is bounded by nothing in the file, so it gets a tighter cap.
    if (!base && count > k_max_accessor_count / 4)
        fail(strf("accessors[%d]: count %zu without a bufferView is more than fovsim accepts", ai, count));
    std::vector<double> out(count * (size_t)comps, 0.0);
    if (base)
        for (size_t i = 0; i < count; i++)
            for (int c = 0; c < comps; c++)
                out[i * comps + c] = decode_component(base + i * stride + (size_t)c * csize,
                                                      a.componentType, a.normalized);

    if (a.sparse.isSparse) {
        const auto &sp = a.sparse;
        if (sp.count < 1 || (size_t)sp.count > count)
            fail(strf("accessors[%d]: sparse.count %d is not in 1..%zu", ai, sp.count, count));
        const int ict = sp.indices.componentType;
        if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(strf("accessors[%d]: sparse.indices.componentType %d is not an unsigned integer type",
                      ai, ict));
        if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
            fail(strf("accessors[%d]: negative sparse byteOffset", ai));
        const size_t isize = (size_t)tinygltf::GetComponentSizeInBytes((uint32_t)ict);
        const size_t n = (size_t)sp.count;
        size_t ilen = 0, vlen = 0;
        const unsigned char *ib = view_bytes(m, sp.indices.bufferView, &ilen);
        const unsigned char *vb = view_bytes(m, sp.values.bufferView, &vlen);
        if (!fits((size_t)sp.indices.byteOffset, n * isize, ilen))
            fail(strf("accessors[%d]: sparse indices exceed bufferView %d (size %zu)", ai,
                      sp.indices.bufferView, ilen));
        if (!fits((size_t)sp.values.byteOffset, n * elem, vlen))
            fail(strf("accessors[%d]: sparse values exceed bufferView %d (size %zu)", ai,
                      sp.values.bufferView, vlen));
        ib += sp.indices.byteOffset;
        vb += sp.values.byteOffset;
        for (size_t k = 0; k < n; k++) {
            size_t idx = (size_t)decode_component(ib + k * isize, ict, false);
            if (idx >= count)
                fail(strf("accessors[%d]: sparse index %zu >= count %zu", ai, idx, count));
            for (int c = 0; c < comps; c++)
                out[idx * comps + c] =
                    decode_component(vb + k * elem + (size_t)c * csize, a.componentType, a.normalized);
        }
    }
    if (comps_out)
        *comps_out = comps;
    return out;
}

// >>images

// Image failures recorded by the image callback, reported only if the image is actually used.
struct uri_state;
struct image_state {
    const tinygltf::Model *model;
    const uri_state *uris;
    std::map<int, std::string> errors;
};

uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

// Width and height from a PNG or JPEG header, so a huge image is refused before it is decoded.
bool peek_image_size(const unsigned char *b, size_t n, uint32_t *w, uint32_t *h)
{
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n >= 24 && memcmp(b, png, 8) == 0) {
        *w = be32(b + 16);
        *h = be32(b + 20);
        return true;
    }
    if (n >= 4 && b[0] == 0xFF && b[1] == 0xD8) {
        size_t i = 2;
        while (i + 9 < n) {
            if (b[i] != 0xFF) {
                i++;
                continue;
            }
            unsigned char mk = b[i + 1];
            if (mk == 0xFF || mk == 0xD8 || mk == 0x01 || (mk >= 0xD0 && mk <= 0xD7)) {
                i += (mk == 0xFF) ? 1 : 2;
                continue;
            }
            if (mk == 0xDA)
                return false; // start of scan without a frame header: let stb_image judge
            size_t seg = (size_t)b[i + 2] << 8 | b[i + 3];
            bool sof = mk >= 0xC0 && mk <= 0xCF && mk != 0xC4 && mk != 0xC8 && mk != 0xCC;
            if (sof) {
                *h = (uint32_t)b[i + 5] << 8 | b[i + 6];
                *w = (uint32_t)b[i + 7] << 8 | b[i + 8];
                return true;
            }
            i += 2 + seg;
        }
    }
    return false;
}

// stb_image 2.27 (Debian's libstb 0.0~git20220908) writes past its Huffman table arrays (size[257],
// values[256]) when a JPEG DHT table declares more than 256 codes: stbi__build_huffman does not
// check the sum of the 16 code counts (later upstream versions do). So a JPEG is refused before
// stb_image sees it if any table it could read declares more. stb_image may read a DHT segment
// wherever the bytes FF C4 stand (after a marker, or after resynchronising past junk or
// entropy-coded data), so every such place is checked as stb reads it (bytes past the end read as
// 0, as its get8 does). Real JPEGs hold a handful of DHT markers (entropy-coded data never holds
// FF C4); more than k_max_dht_markers is refused unchecked, which keeps the check linear. Returns
// why it is refused, or "".
const size_t k_max_dht_markers = 1024;
std::string jpeg_huffman_problem(const unsigned char *b, size_t n)
{
    auto get = [&](size_t i) -> size_t { return i < n ? b[i] : 0; };
    size_t markers = 0;
    for (size_t j = 0; j + 1 < n; j++) {
        if (b[j] != 0xFF || b[j + 1] != 0xC4)
            continue;
        if (++markers > k_max_dht_markers)
            return strf("corrupt JPEG: more than %zu Huffman table markers (FF C4)", k_max_dht_markers);
        size_t p = j + 2;
        long left = (long)(get(p) << 8 | get(p + 1)) - 2; // the segment's length, less its own 2 bytes
        p += 2;
        while (left > 0 && p < n) { // past the end every count reads 0: nothing more to check
            size_t codes = 0;
            for (size_t i = 0; i < 16; i++)
                codes += get(p + 1 + i); // after the table class/id byte
            if (codes > 256)
                return strf("corrupt JPEG: a Huffman table declares %zu codes (at most 256)", codes);
            p += 17 + codes;
            left -= (long)(17 + codes);
        }
    }
    return std::string();
}

// A PNG's pixel data inflates to exactly what its header declares (PNG spec 10.2 and 8.2): height
// rows of 1 + ceil(width * bits per pixel / 8) bytes, per Adam7 pass when interlaced. stb_image
// inflates the whole IDAT stream into a growing buffer before it compares (and accepts extra data
// after an interlaced image), so a 2 MB stream declaring 1x1 pixels took 2 GiB (README "Limits"). So the
// stream is inflated here, by zlib, into a buffer of the declared size and no more: a stream that
// would fill more is refused after one byte too many. The pixels then reach stb_image as a PNG of
// the same chunks whose IDAT holds them in stored (uncompressed) deflate blocks, which it copies
// instead of inflating again: the pixel budget, checked against the header, bounds the memory,
// and each stream is inflated once. Returns why the PNG is refused, or "" with *out the rewritten
// PNG, or "" with *out empty when stb_image reads the original (no IHDR, no pixels, a stream that
// ends short: what it refuses itself, bounded by the declared size).
std::string png_bounded(const unsigned char *b, size_t n, std::vector<unsigned char> *out)
{
    out->clear();
    // The chunks as stb_image walks them: length, type, data, CRC; a truncated one ends the walk.
    std::vector<std::pair<size_t, size_t>> chunks; // (offset of the length field, data length)
    for (size_t i = 8; i + 8 <= n;) {
        const size_t len = std::min((size_t)be32(b + i), n - i - 8);
        chunks.emplace_back(i, len);
        if (memcmp(b + i + 4, "IEND", 4) == 0)
            break;
        i += 12 + len;
    }
    auto is = [&](const std::pair<size_t, size_t> &c, const char *t) { return memcmp(b + c.first + 4, t, 4) == 0; };
    const unsigned char *ihdr = nullptr;
    bool raw_deflate = false; // Apple's CgBI PNGs hold a raw deflate stream (stb_image reads them)
    for (const auto &c : chunks) {
        raw_deflate = raw_deflate || is(c, "CgBI");
        if (is(c, "IHDR") && c.second >= 13) {
            ihdr = b + c.first + 8;
            break;
        }
    }
    if (!ihdr)
        return std::string(); // stb_image refuses it ("first not IHDR")
    const uint64_t w = be32(ihdr), h = be32(ihdr + 4);
    const unsigned depth = ihdr[8], ctype = ihdr[9], interlace = ihdr[12];
    const unsigned channels = ctype == 0 ? 1 : ctype == 2 ? 3 : ctype == 3 ? 1 : ctype == 4 ? 2 : ctype == 6 ? 4 : 0;
    if (!channels || !depth || depth > 16 || interlace > 1)
        return std::string(); // stb_image refuses these by name
    const uint64_t bpp = (uint64_t)channels * depth; // bits per pixel
    auto rows = [&](uint64_t pw, uint64_t ph) -> uint64_t { return pw && ph ? ph * (1 + (pw * bpp + 7) / 8) : 0; };
    uint64_t expect = 0;
    if (!interlace) {
        expect = rows(w, h);
    } else {
        static const int xo[7] = {0, 4, 0, 2, 0, 1, 0}, yo[7] = {0, 0, 4, 0, 2, 0, 1};
        static const int xs[7] = {8, 8, 4, 4, 2, 2, 1}, ys[7] = {8, 8, 8, 4, 4, 2, 2};
        for (int p = 0; p < 7; p++)
            expect += rows(w > (uint64_t)xo[p] ? (w - xo[p] + xs[p] - 1) / xs[p] : 0,
                           h > (uint64_t)yo[p] ? (h - yo[p] + ys[p] - 1) / ys[p] : 0);
    }
    if (expect == 0)
        return std::string();
    const uint64_t block = 65535, blocks = (expect + block - 1) / block;
    const uint64_t idat_len = (raw_deflate ? 0 : 2 + 4) + blocks * 5 + expect;
    if (idat_len > (uint64_t)INT_MAX - n)
        return strf("%llux%llu pixels of %u bits are more than fovsim decodes in one image (2 GiB)",
                    (unsigned long long)w, (unsigned long long)h, (unsigned)bpp);

    // The new IDAT's data: [zlib header] blocks of 5 header bytes + up to 65535 pixel bytes, [Adler-32].
    std::vector<unsigned char> idat((size_t)idat_len);
    size_t o = raw_deflate ? 0 : 2;
    if (!raw_deflate) {
        idat[0] = 0x78; // deflate, 32K window
        idat[1] = 0x01; // (0x78 * 256 + 0x01) % 31 == 0
    }
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, raw_deflate ? -15 : 15) != Z_OK)
        throw std::bad_alloc();
    uint64_t total = 0;
    unsigned char spare[64]; // where a stream that goes on past the declared size is caught
    std::string why;
    bool ended = false;
    size_t slot = 0, slot_left = 0; // the current block's next free byte, and how many are left in it
    for (const auto &c : chunks) {
        if (ended || !why.empty())
            break;
        if (!is(c, "IDAT"))
            continue;
        z.next_in = const_cast<unsigned char *>(b + c.first + 8);
        z.avail_in = (uInt)c.second;
        while (z.avail_in > 0 && !ended && why.empty()) {
            if (slot_left == 0 && total < expect) { // open the next stored block
                const size_t len = (size_t)std::min(block, expect - total);
                idat[o] = total + len == expect ? 1 : 0; // BFINAL on the last; BTYPE 00, stored
                idat[o + 1] = (unsigned char)(len & 0xFF);
                idat[o + 2] = (unsigned char)(len >> 8);
                idat[o + 3] = (unsigned char)(~len & 0xFF);
                idat[o + 4] = (unsigned char)((~len >> 8) & 0xFF);
                slot = o + 5;
                slot_left = len;
                o += 5 + len;
            }
            const bool full = total == expect;
            z.next_out = full ? spare : idat.data() + slot;
            z.avail_out = (uInt)(full ? sizeof spare : slot_left);
            const uInt before = z.avail_out;
            const int r = inflate(&z, Z_NO_FLUSH);
            const size_t got = before - z.avail_out;
            if (full && got > 0) {
                why = strf("the PNG's pixel data inflates to more than the %llu bytes its %llux%llu pixels need "
                           "(a corrupt PNG or a decompression bomb)",
                           (unsigned long long)expect, (unsigned long long)w, (unsigned long long)h);
                break;
            }
            if (!full) {
                slot += got;
                slot_left -= got;
                total += got;
            }
            if (r == Z_MEM_ERROR) {
                inflateEnd(&z);
                throw std::bad_alloc();
            } else if (r == Z_DATA_ERROR && z.msg && strcmp(z.msg, "incorrect data check") == 0) {
                ended = true; // everything inflated; stb_image does not check the Adler-32 either
            } else if (r == Z_DATA_ERROR || r == Z_NEED_DICT) {
                why = strf("corrupt PNG: its compressed pixel data is not a valid zlib stream (%s)",
                           z.msg ? z.msg : "it needs a preset dictionary");
            } else if (r == Z_STREAM_END || (r != Z_OK && r != Z_BUF_ERROR)) {
                ended = true;
            }
        }
    }
    const uLong z_adler = z.adler;
    inflateEnd(&z);
    if (!why.empty() || total < expect)
        return why; // too short: stb_image says so of the original (which inflates to less than this)
    if (!raw_deflate) { // zlib kept the Adler-32 of what it inflated
        const uLong adler = z_adler;
        idat[o++] = (unsigned char)(adler >> 24);
        idat[o++] = (unsigned char)(adler >> 16);
        idat[o++] = (unsigned char)(adler >> 8);
        idat[o++] = (unsigned char)adler;
    }
    // The PNG again: every chunk but the IDATs as it was, the new IDAT where the first one stood.
    out->reserve(n + idat.size());
    out->insert(out->end(), b, b + 8);
    bool placed = false;
    for (const auto &c : chunks) {
        if (is(c, "IDAT")) {
            if (placed)
                continue;
            placed = true;
            unsigned char head[8] = {(unsigned char)(idat.size() >> 24), (unsigned char)(idat.size() >> 16),
                                     (unsigned char)(idat.size() >> 8), (unsigned char)idat.size(), 'I', 'D', 'A', 'T'};
            out->insert(out->end(), head, head + 8);
            out->insert(out->end(), idat.begin(), idat.end());
            const unsigned char tail[4] = {0, 0, 0, 0}; // the CRC: stb_image reads past it unchecked
            out->insert(out->end(), tail, tail + 4);
            std::vector<unsigned char>().swap(idat);
            continue;
        }
        const size_t end = std::min(n, c.first + 12 + c.second);
        out->insert(out->end(), b + c.first, b + end);
    }
    return std::string();
}

// tinygltf's image callback: checks the bytes tinygltf hands over (for a bufferView image it does
// not check the view against its buffer), then decodes with tinygltf's own stb_image loader, which
// expands every image to 4 channels (8 or 16 bits). A failure is recorded, not returned, so that an
// undecodable image nobody uses (a KTX2 normal map, say) does not fail the whole asset.
bool load_image_cb(tinygltf::Image *image, const int idx, std::string *err, std::string *warn,
                   int req_w, int req_h, const unsigned char *bytes, int size, void *user)
{
    (void)err;
    image_state *st = static_cast<image_state *>(user);
    if (image->bufferView >= 0) {
        const tinygltf::Model &m = *st->model;
        if ((size_t)image->bufferView >= m.bufferViews.size()) {
            st->errors[idx] = strf("bufferView %d does not exist", image->bufferView);
            return true;
        }
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)image->bufferView];
        if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size() ||
            !fits(bv.byteOffset, bv.byteLength, m.buffers[(size_t)bv.buffer].data.size()) ||
            bv.byteLength > (size_t)INT_MAX) {
            st->errors[idx] = strf("bufferViews[%d]: byteOffset + byteLength exceeds its buffer",
                                   image->bufferView);
            return true;
        }
    }
    if (!bytes || size <= 0) {
        st->errors[idx] = "no image data";
        return true;
    }
    // The declared size decides, before anything is decoded (a 1 MB PNG may declare 16384 x 16384).
    uint32_t w = 0, h = 0;
    if (!peek_image_size(bytes, (size_t)size, &w, &h)) {
        st->errors[idx] = "expected a PNG or JPEG image (the formats glTF allows), found no PNG or JPEG header";
        return true;
    }
    if (w > MAX_TEXTURE_SIZE || h > MAX_TEXTURE_SIZE) {
        st->errors[idx] = strf("%ux%u is larger than MAX_TEXTURE_SIZE (%d)", w, h, MAX_TEXTURE_SIZE);
        return true;
    }
    const uint64_t px = (uint64_t)w * h;
    if (px > g_image_budget) {
        st->errors[idx] = strf("%ux%u is %.1f Mpixel, over the budget of %.1f Mpixel per image "
                               "(--max-image-mpixels raises it)", w, h, (double)px / (1 << 20),
                               (double)g_image_budget / (1 << 20));
        return true;
    }
    if (px > g_scene_budget || g_scene_pixels > g_scene_budget - px) {
        st->errors[idx] = strf("%ux%u (%.1f Mpixel) would bring the scene's images to %.1f Mpixel, over the "
                               "budget of %.1f Mpixel per scene (--max-scene-mpixels raises it)", w, h,
                               (double)px / (1 << 20), (double)(g_scene_pixels + px) / (1 << 20),
                               (double)g_scene_budget / (1 << 20));
        return true;
    }
    std::vector<unsigned char> png; // the PNG with its pixels inflated once, within the declared size
    {
        // JPEG (peek_image_size found its SOI) or PNG
        std::string why = bytes[0] == 0xFF ? jpeg_huffman_problem(bytes, (size_t)size)
                                           : png_bounded(bytes, (size_t)size, &png);
        if (!why.empty()) {
            st->errors[idx] = why;
            return true;
        }
    }
    g_scene_pixels += px;
    std::string e;
    if (!png.empty()) {
        bytes = png.data();
        size = (int)png.size();
    }
    if (!tinygltf::LoadImageData(image, idx, &e, warn, req_w, req_h, bytes, size, nullptr)) {
        std::string line = first_line(e);
        st->errors[idx] = line.empty() ? "cannot decode" : line;
        image->image.clear();
    }
    return true;
}

std::string image_label(const tinygltf::Image &im)
{
    if (!im.name.empty())
        return im.name;
    if (!im.uri.empty() && im.uri.compare(0, 5, "data:") != 0)
        return im.uri;
    return std::string();
}

// Converts decoded image `src` to RGBA8 (1/2/3 channels expanded, alpha 255 when absent; 16-bit
// rounded to 8-bit).
image_rgba8 convert_image(const tinygltf::Model &m, const image_state &st, int src)
{
    const tinygltf::Image &im = m.images[(size_t)src];
    const std::string label = image_label(im);
    const std::string where =
        label.empty() ? strf("images[%d]", src) : strf("images[%d] (%s)", src, label.c_str());
    auto it = st.errors.find(src);
    if (it != st.errors.end())
        fail(where + ": " + it->second);
    if (im.image.empty() || im.width < 1 || im.height < 1) {
        // refused by the URI rule: say why (the key is the path tinygltf built from the URI)
        for (const auto &kv : st.uris->refusals)
            if (!im.uri.empty() && kv.first.size() >= im.uri.size() &&
                kv.first.compare(kv.first.size() - im.uri.size(), im.uri.size(), im.uri) == 0)
                fail(where + ": " + kv.second);
        fail(where + ": could not be loaded (missing or unreadable file)");
    }
    if (im.width > MAX_TEXTURE_SIZE || im.height > MAX_TEXTURE_SIZE)
        fail(strf("%s: %dx%d is larger than MAX_TEXTURE_SIZE (%d)", where.c_str(), im.width, im.height,
                  MAX_TEXTURE_SIZE));
    const int comps = im.component;
    const int bytes_per = im.bits == 16 ? 2 : im.bits == 8 ? 1 : 0;
    if (comps < 1 || comps > 4 || !bytes_per)
        fail(strf("%s: unsupported pixel format (%d channels, %d bits)", where.c_str(), comps, im.bits));
    const size_t texels = (size_t)im.width * (size_t)im.height;
    if (im.image.size() < texels * (size_t)comps * (size_t)bytes_per)
        fail(where + ": decoded data is shorter than width * height");

    image_rgba8 out;
    memset(&out, 0, sizeof out);
    out.width = im.width;
    out.height = im.height;
    copy_name(out.name, sizeof out.name, label);
    out.rgba = static_cast<uint8_t *>(malloc(texels * 4));
    if (!out.rgba)
        throw std::bad_alloc();
    const unsigned char *s = im.image.data();
    for (size_t t = 0; t < texels; t++) {
        uint8_t ch[4];
        for (int c = 0; c < comps; c++) {
            if (bytes_per == 1) {
                ch[c] = s[(t * comps + c)];
            } else {
                uint16_t v;
                memcpy(&v, s + 2 * (t * comps + c), 2);
                ch[c] = (uint8_t)((v * 255u + 32767u) / 65535u);
            }
        }
        uint8_t *d = out.rgba + 4 * t;
        switch (comps) {
        case 1: d[0] = d[1] = d[2] = ch[0]; d[3] = 255; break;
        case 2: d[0] = d[1] = d[2] = ch[0]; d[3] = ch[1]; break;
        case 3: d[0] = ch[0]; d[1] = ch[1]; d[2] = ch[2]; d[3] = 255; break;
        default: memcpy(d, ch, 4); break;
        }
    }
    return out;
}

// >>materials

tex_wrap convert_wrap(const char *path, int w)
{
    switch (w) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return TEX_WRAP_REPEAT;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TEX_WRAP_CLAMP;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TEX_WRAP_MIRROR;
    default:
        log_warn("%s: unknown sampler wrap mode %d, using REPEAT", path, w);
        return TEX_WRAP_REPEAT;
    }
}

material make_default_material()
{
    material d;
    memset(&d, 0, sizeof d);
    copy_name(d.name, sizeof d.name, "default");
    for (float &c : d.base_color)
        c = 1.0f;
    d.base_color_image = -1;
    d.wrap_s = d.wrap_t = TEX_WRAP_REPEAT;
    d.mag_filter = TEX_FILTER_LINEAR;
    d.alpha_kind = ALPHA_KIND_OPAQUE;
    d.alpha_cutoff = 0.5f;
    d.double_sided = false;
    d.alpha_mode = ALPHA_MODE_DEFAULT;
    return d;
}

// Converts every glTF material (same indices) and keeps the images they use as base colour.
void convert_materials(const char *path, const tinygltf::Model &m, const image_state &st, builder &b)
{
    std::vector<int> image_map(m.images.size(), -1); // glTF image -> asset image
    for (size_t mi = 0; mi < m.materials.size(); mi++) {
        const tinygltf::Material &gm = m.materials[mi];
        material d = make_default_material();
        copy_name(d.name, sizeof d.name, gm.name);
        const std::vector<double> &f = gm.pbrMetallicRoughness.baseColorFactor;
        if (f.size() == 4)
            for (int c = 0; c < 4; c++)
                d.base_color[c] = (float)f[(size_t)c];
        else if (!f.empty())
            fail(strf("materials[%zu]: baseColorFactor has %zu numbers, expected 4", mi, f.size()));

        const tinygltf::TextureInfo &ti = gm.pbrMetallicRoughness.baseColorTexture;
        if (ti.index >= 0) {
            if ((size_t)ti.index >= m.textures.size())
                fail(strf("materials[%zu]: baseColorTexture %d does not exist (the file has %zu)", mi,
                          ti.index, m.textures.size()));
            if (ti.texCoord != 0)
                log_warn("%s: materials[%zu]: baseColorTexture uses TEXCOORD_%d; fovsim reads TEXCOORD_0",
                         path, mi, ti.texCoord);
            const tinygltf::Texture &t = m.textures[(size_t)ti.index];
            if (t.sampler >= 0) {
                if ((size_t)t.sampler >= m.samplers.size())
                    fail(strf("textures[%d]: sampler %d does not exist (the file has %zu)", ti.index,
                              t.sampler, m.samplers.size()));
                const tinygltf::Sampler &s = m.samplers[(size_t)t.sampler];
                d.wrap_s = convert_wrap(path, s.wrapS);
                d.wrap_t = convert_wrap(path, s.wrapT);
                d.mag_filter = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? TEX_FILTER_NEAREST
                                                                              : TEX_FILTER_LINEAR;
            }
            if (t.source < 0) {
                log_warn("%s: textures[%d] has no image source; materials[%zu] is drawn untextured",
                         path, ti.index, mi);
            } else {
                if ((size_t)t.source >= m.images.size())
                    fail(strf("textures[%d]: source %d does not exist (the file has %zu images)",
                              ti.index, t.source, m.images.size()));
                int &slot = image_map[(size_t)t.source];
                if (slot < 0) {
                    b.images.push_back(image_rgba8{});
                    b.images.back() = convert_image(m, st, t.source);
                    slot = (int)b.images.size() - 1;
                }
                d.base_color_image = slot;
            }
        }

        if (gm.alphaMode == "MASK")
            d.alpha_kind = ALPHA_KIND_MASK;
        else if (gm.alphaMode == "BLEND")
            d.alpha_kind = ALPHA_KIND_BLEND;
        else if (gm.alphaMode == "OPAQUE" || gm.alphaMode.empty())
            d.alpha_kind = ALPHA_KIND_OPAQUE;
        else
            fail(strf("materials[%zu]: unknown alphaMode \"%s\"", mi, gm.alphaMode.c_str()));
        d.alpha_cutoff = (float)gm.alphaCutoff;
        d.double_sided = gm.doubleSided;
        b.materials.push_back(d);
    }
}

// >>primitives

// One glTF primitive decoded once (in mesh space), emitted once per node that uses its mesh.
struct decoded_prim {
    bool skip = false;
    size_t vertex_count = 0;
    std::vector<float> pos, nrm, uv, col; // nrm empty: computed after the transform
    std::vector<uint32_t> idx;            // triangle list
    int material = -1;
};

const int k_types_vec2[] = {TINYGLTF_TYPE_VEC2, 0};
const int k_types_vec3[] = {TINYGLTF_TYPE_VEC3, 0};
const int k_types_color[] = {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4, 0};
const int k_types_scalar[] = {TINYGLTF_TYPE_SCALAR, 0};

std::vector<double> read_attribute(const tinygltf::Model &m, const tinygltf::Primitive &p,
                                   const char *name, const int *types, size_t vertex_count,
                                   const std::string &where, int *comps)
{
    auto it = p.attributes.find(name);
    if (it == p.attributes.end())
        return std::vector<double>();
    const std::string what = where + "." + name;
    std::vector<double> v = read_accessor(m, it->second, what.c_str(), types, comps);
    if (vertex_count != (size_t)-1 && v.size() != vertex_count * (size_t)*comps)
        fail(strf("%s: %s has %zu elements but POSITION has %zu", where.c_str(), name,
                  v.size() / (size_t)*comps, vertex_count));
    return v;
}

decoded_prim decode_prim(const char *path, const tinygltf::Model &m, size_t mesh_i, size_t prim_i)
{
    const tinygltf::Primitive &p = m.meshes[mesh_i].primitives[prim_i];
    const std::string where = strf("meshes[%zu].primitives[%zu]", mesh_i, prim_i);
    decoded_prim d;
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode < TINYGLTF_MODE_TRIANGLES) {
        log_warn("%s: %s: points and lines (mode %d) are not drawn, skipped", path, where.c_str(), mode);
        d.skip = true;
        return d;
    }
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
        fail(strf("%s: mode %d is not a glTF primitive mode", where.c_str(), mode));
    if (!p.targets.empty())
        log_warn("%s: %s: morph targets are ignored (drawn in the base pose)", path, where.c_str());

    if (p.attributes.find("POSITION") == p.attributes.end())
        fail(where + ": has no POSITION attribute");
    int comps = 0;
    std::vector<double> pos = read_attribute(m, p, "POSITION", k_types_vec3, (size_t)-1, where, &comps);
    const size_t n = pos.size() / 3;
    if (n > (size_t)UINT32_MAX)
        fail(where + ": too many vertices");
    d.vertex_count = n;
    d.pos.assign(pos.begin(), pos.end());

    std::vector<double> nrm = read_attribute(m, p, "NORMAL", k_types_vec3, n, where, &comps);
    d.nrm.assign(nrm.begin(), nrm.end());
    std::vector<double> uv = read_attribute(m, p, "TEXCOORD_0", k_types_vec2, n, where, &comps);
    if (uv.empty())
        d.uv.assign(n * 2, 0.0f);
    else
        d.uv.assign(uv.begin(), uv.end());
    comps = 0;
    std::vector<double> col = read_attribute(m, p, "COLOR_0", k_types_color, n, where, &comps);
    d.col.assign(n * 4, 1.0f);
    if (!col.empty()) {
        // Integer colours must be normalized (glTF 2.0 spec, "Meshes"); they are read as such even
        // when the flag is missing, since an unnormalized 0..255 colour is never what was meant.
        auto it = p.attributes.find("COLOR_0");
        const tinygltf::Accessor &a = m.accessors[(size_t)it->second];
        double scale = 1.0;
        if (!a.normalized && a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
            scale = 1.0 / 255.0;
        else if (!a.normalized && a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
            scale = 1.0 / 65535.0;
        for (size_t v = 0; v < n; v++)
            for (int c = 0; c < comps; c++)
                d.col[v * 4 + c] = (float)(col[v * comps + c] * scale);
    }

    // Source index list (explicit or 0..n-1), every index checked against the vertex count.
    std::vector<uint32_t> src;
    if (p.indices >= 0) {
        const tinygltf::Accessor *ia =
            (size_t)p.indices < m.accessors.size() ? &m.accessors[(size_t)p.indices] : nullptr;
        if (ia && ia->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            ia->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ia->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(strf("accessors[%d]: componentType %d is not valid for indices", p.indices,
                      ia->componentType));
        const std::string what = where + ".indices";
        std::vector<double> iv = read_accessor(m, p.indices, what.c_str(), k_types_scalar, &comps);
        src.resize(iv.size());
        for (size_t k = 0; k < iv.size(); k++) {
            uint32_t i = (uint32_t)iv[k];
            if (i >= n)
                fail(strf("%s: index %u >= %zu vertices", where.c_str(), i, n));
            src[k] = i;
        }
    } else {
        src.resize(n);
        for (size_t k = 0; k < n; k++)
            src[k] = (uint32_t)k;
    }

    // Triangle list (glTF 2.0 spec, "Meshes": strips alternate winding, fans pivot on the first vertex).
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (src.size() % 3)
            log_warn("%s: %s: %zu indices is not a multiple of 3; the last %zu are ignored", path,
                     where.c_str(), src.size(), src.size() % 3);
        src.resize(src.size() - src.size() % 3);
        d.idx = std::move(src);
    } else {
        for (size_t i = 0; i + 2 < src.size(); i++) {
            uint32_t t[3];
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                t[0] = src[i];
                t[1] = src[i + 1 + (i & 1)];
                t[2] = src[i + 2 - (i & 1)];
            } else {
                t[0] = src[i + 1];
                t[1] = src[i + 2];
                t[2] = src[0];
            }
            d.idx.insert(d.idx.end(), t, t + 3);
        }
    }
    if (d.idx.empty() || n == 0) {
        log_info("%s: %s has no triangles, skipped", path, where.c_str());
        d.skip = true;
    }
    d.material = p.material;
    return d;
}

// >>nodes

struct flattener {
    const char *path;
    const tinygltf::Model &m;
    builder &b;
    std::map<size_t, std::vector<decoded_prim>> cache; // mesh -> decoded primitives
    std::vector<char> on_path;                          // cycle detection
    std::vector<char> visited;                          // nodes reached so far: each at most once
    int default_material = -1;
    asset_camera camera{};
    bool warned_skin = false;

    flattener(const char *p, const tinygltf::Model &model, builder &bl)
        : path(p), m(model), b(bl), on_path(model.nodes.size(), 0), visited(model.nodes.size(), 0)
    {
    }

    mat4 local_matrix(size_t ni)
    {
        const tinygltf::Node &n = m.nodes[ni];
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16)
                fail(strf("nodes[%zu]: matrix has %zu numbers, expected 16", ni, n.matrix.size()));
            mat4 r;
            for (int k = 0; k < 16; k++)
                r.m[k] = (float)n.matrix[(size_t)k]; // both column-major
            return r;
        }
        float t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
        auto take = [&](const std::vector<double> &v, float *dst, size_t want, const char *name) {
            if (v.empty())
                return;
            if (v.size() != want)
                fail(strf("nodes[%zu]: %s has %zu numbers, expected %zu", ni, name, v.size(), want));
            for (size_t k = 0; k < want; k++)
                dst[k] = (float)v[k];
        };
        take(n.translation, t, 3, "translation");
        take(n.rotation, q, 4, "rotation");
        take(n.scale, s, 3, "scale");
        // Exporters write quaternions rounded to a few digits; m4_quat wants unit length.
        float ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(ql > 0.0f) || !std::isfinite(ql))
            fail(strf("nodes[%zu]: rotation is not a valid quaternion", ni));
        for (float &c : q)
            c /= ql;
        return m4_trs(t, q, s);
    }

    static float det3(const mat4 &a)
    {
        const float *m = a.m;
        return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
               m[8] * (m[1] * m[6] - m[5] * m[2]);
    }

    template <class T> static T *alloc(size_t n)
    {
        T *p = static_cast<T *>(malloc(n * sizeof(T)));
        if (!p)
            throw std::bad_alloc();
        return p;
    }

    void emit(size_t mesh_i, const mat4 &world)
    {
        auto it = cache.find(mesh_i);
        if (it == cache.end()) {
            std::vector<decoded_prim> v;
            const tinygltf::Mesh &mesh = m.meshes[mesh_i];
            for (size_t pi = 0; pi < mesh.primitives.size(); pi++)
                v.push_back(decode_prim(path, m, mesh_i, pi));
            it = cache.emplace(mesh_i, std::move(v)).first;
        }
        const mat4 nm = m4_normal_matrix(world);
        // Mirrored: swap winding so front faces stay front (glTF 2.0 spec, "Transformations").
        const bool flip = det3(world) < 0.0f;
        for (size_t pi = 0; pi < it->second.size(); pi++) {
            const decoded_prim &d = it->second[pi];
            if (d.skip)
                continue;
            int mat = d.material;
            if (mat >= (int)m.materials.size())
                fail(strf("meshes[%zu].primitives[%zu]: material %d does not exist (the file has %zu)",
                          mesh_i, pi, mat, m.materials.size()));
            if (mat < 0) {
                if (default_material < 0) {
                    b.materials.push_back(make_default_material());
                    default_material = (int)b.materials.size() - 1;
                }
                mat = default_material;
            }
            const size_t n = d.vertex_count;
            b.prims.push_back(prim{});
            prim &p = b.prims.back();
            memset(&p, 0, sizeof p);
            p.material = mat;
            p.vertex_count = (uint32_t)n;
            p.index_count = (uint32_t)d.idx.size();
            p.positions = alloc<float>(n * 3);
            p.normals = alloc<float>(n * 3);
            p.uvs = alloc<float>(n * 2);
            p.colors = alloc<float>(n * 4);
            p.indices = alloc<uint32_t>(d.idx.size());
            for (size_t v = 0; v < n; v++) {
                vec3 q = m4_point(world, v3(d.pos[3 * v], d.pos[3 * v + 1], d.pos[3 * v + 2]));
                p.positions[3 * v] = q.x;
                p.positions[3 * v + 1] = q.y;
                p.positions[3 * v + 2] = q.z;
            }
            memcpy(p.uvs, d.uv.data(), n * 2 * sizeof(float));
            memcpy(p.colors, d.col.data(), n * 4 * sizeof(float));
            memcpy(p.indices, d.idx.data(), d.idx.size() * sizeof(uint32_t));
            if (flip)
                for (size_t t = 0; t + 2 < d.idx.size(); t += 3)
                    std::swap(p.indices[t + 1], p.indices[t + 2]);
            if (d.nrm.empty()) {
                prim_compute_normals(&p); // from the transformed, re-wound triangles
            } else {
                for (size_t v = 0; v < n; v++) {
                    vec3 q = m4_dir(nm, v3(d.nrm[3 * v], d.nrm[3 * v + 1], d.nrm[3 * v + 2]));
                    q = v3_norm_or(q, v3(0, 1, 0));
                    p.normals[3 * v] = q.x;
                    p.normals[3 * v + 1] = q.y;
                    p.normals[3 * v + 2] = q.z;
                }
            }
        }
    }

    void take_camera(size_t ni, const mat4 &world)
    {
        const tinygltf::Node &n = m.nodes[ni];
        if (camera.present || n.camera < 0)
            return;
        if ((size_t)n.camera >= m.cameras.size())
            fail(strf("nodes[%zu]: camera %d does not exist (the file has %zu)", ni, n.camera,
                      m.cameras.size()));
        const tinygltf::Camera &c = m.cameras[(size_t)n.camera];
        if (c.type != "perspective")
            return;
        const double yfov = c.perspective.yfov;
        if (!(yfov > 0.0 && yfov < FS_PI)) {
            log_warn("%s: cameras[%d]: yfov %g is not in (0, pi), camera ignored", path, n.camera, yfov);
            return;
        }
        const double aspect = c.perspective.aspectRatio > 0.0 ? c.perspective.aspectRatio : 16.0 / 9.0;
        camera.present = true;
        camera.position = m4_point(world, v3(0, 0, 0));
        vec3 fwd = v3_norm_or(m4_dir(world, v3(0, 0, -1)), v3(0, 0, -1)); // glTF cameras look down -Z
        camera.target = v3_add(camera.position, fwd);
        camera.hfov_deg = (float)(2.0 * std::atan(std::tan(yfov * 0.5) * aspect) * 180.0 / FS_PI);
    }

    void visit(int node, const mat4 &parent, int depth)
    {
        if (node < 0 || (size_t)node >= m.nodes.size())
            fail(strf("node %d does not exist (the file has %zu)", node, m.nodes.size()));
        const size_t ni = (size_t)node;
        if (on_path[ni])
            fail(strf("nodes[%zu]: the node hierarchy has a cycle", ni));
        // glTF 2.0 ("Nodes and Hierarchy"): the hierarchy is a set of disjoint trees, no node has
        // two parents. A node reached twice would be drawn twice, and a chain of nodes that each
        // list the next one twice doubles the work at every level (40 levels in 1 KB: a hang).
        if (visited[ni])
            fail(strf("nodes[%zu]: the node is reached twice (a second parent, or listed twice); "
                      "glTF node hierarchies are disjoint trees", ni));
        visited[ni] = 1;
        if (depth >= MAX_GLTF_NODE_DEPTH)
            fail(strf("nodes[%zu]: the node hierarchy is deeper than %d levels", ni, MAX_GLTF_NODE_DEPTH));
        const tinygltf::Node &n = m.nodes[ni];
        const mat4 world = m4_mul(parent, local_matrix(ni));
        if (n.mesh >= 0) {
            if ((size_t)n.mesh >= m.meshes.size())
                fail(strf("nodes[%zu]: mesh %d does not exist (the file has %zu)", ni, n.mesh,
                          m.meshes.size()));
            if (n.skin >= 0 && !warned_skin) {
                log_warn("%s: skinned meshes are drawn in their bind pose", path);
                warned_skin = true;
            }
            emit((size_t)n.mesh, world);
        }
        take_camera(ni, world);
        on_path[ni] = 1;
        for (int c : n.children)
            visit(c, world, depth + 1);
        on_path[ni] = 0;
    }

    void run()
    {
        std::vector<int> roots;
        if (!m.scenes.empty()) {
            int s = m.defaultScene >= 0 ? m.defaultScene : 0;
            if ((size_t)s >= m.scenes.size())
                fail(strf("scene %d does not exist (the file has %zu)", s, m.scenes.size()));
            roots = m.scenes[(size_t)s].nodes;
        } else {
            // No scenes: every node that is nobody's child is a root.
            std::vector<char> child(m.nodes.size(), 0);
            for (const tinygltf::Node &n : m.nodes)
                for (int c : n.children)
                    if (c >= 0 && (size_t)c < child.size())
                        child[(size_t)c] = 1;
            for (size_t i = 0; i < m.nodes.size(); i++)
                if (!child[i])
                    roots.push_back((int)i);
        }
        const mat4 id = m4_identity();
        for (int r : roots)
            visit(r, id, 0);
    }
};

// >>entry

fs_status load(const char *path, asset *out)
{
    const std::string spath(path);
    std::vector<unsigned char> data = read_file(spath);
    if (data.empty())
        fail("empty file");
    if (data.size() > (size_t)UINT_MAX)
        fail("file is larger than 4 GiB");
    // The magic wins over the extension, so a misnamed .glb still loads.
    const bool binary = ends_with_ci(spath, ".glb") ||
                        (data.size() >= 4 && memcmp(data.data(), "glTF", 4) == 0);
    if (binary) {
        // GLB: 12-byte header (magic, version, length), then chunk 0 (length, type, data) holds the
        // JSON. Its length is clamped to the file; tinygltf judges a malformed header, but reads a
        // version-1 header as version 2: refused here.
        if (data.size() >= 8) {
            uint32_t version;
            memcpy(&version, data.data() + 4, 4);
            if (version != 2)
                fail(strf("GLB version %u (expected 2: glTF 2.0 binary)", version));
        }
        if (data.size() >= 20) {
            uint32_t len;
            memcpy(&len, data.data() + 12, 4);
            const size_t jn = std::min((size_t)len, data.size() - 20);
            check_json_depth(data.data() + 20, jn, 20);
            check_json_indices(data.data() + 20, jn);
        }
    } else {
        check_json_depth(data.data(), data.size(), 0);
        check_json_indices(data.data(), data.size());
    }
    const size_t slash = spath.find_last_of('/');
    const std::string base_dir = slash == std::string::npos ? std::string()
                                 : slash == 0                ? std::string("/")
                                                             : spath.substr(0, slash);

    uri_state u;
    u.base_dir = base_dir;
    {
        char real[PATH_MAX];
        if (!realpath(base_dir.empty() ? "." : base_dir.c_str(), real))
            fail(strf("cannot resolve its folder: %s", strerror(errno)), FS_ERR_IO);
        u.root = real;
    }
    tinygltf::Model model;
    image_state st;
    st.model = &model;
    st.uris = &u;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(load_image_cb, &st);
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fs_file_exists, fs_expand, fs_read, fs_write, &u});
    std::string err, warn;
    bool ok;
    if (binary)
        ok = loader.LoadBinaryFromMemory(&model, &err, &warn, data.data(), (unsigned)data.size(), base_dir);
    else
        ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char *>(data.data()),
                                        (unsigned)data.size(), base_dir);
    std::vector<unsigned char>().swap(data);
    check_extensions(path, model, ok);
    if (!ok) {
        std::string line = first_line(err);
        // A buffer refused by the URI rule: say why, not tinygltf's "File not found".
        if (!u.last.empty() && (line.compare(0, 14, "File not found") == 0 || line.compare(0, 15, "File read error") == 0))
            fail(u.last);
        fail(line.empty() ? std::string("tinygltf could not load the file") : line);
    }
    // tinygltf's warning (an image it could not read, say), or why the URI rule refused one: shown
    // once the asset has loaded, so that a failing load prints only its one error line.
    const std::string wline = !u.refusals.empty() ? u.refusals.begin()->second : first_line(warn);

    builder b;
    convert_materials(path, model, st, b);
    flattener fl(path, model, b);
    fl.run();
    if (b.prims.empty())
        fail("the default scene has no triangles to draw");
    if (b.prims.size() > (size_t)INT_MAX || b.materials.size() > (size_t)INT_MAX)
        fail("too many primitives");

    asset a;
    memset(&a, 0, sizeof a);
    copy_name(a.name, sizeof a.name, base_name(spath));
    a.source = ASSET_SOURCE_GLTF;
    a.camera = fl.camera;
    // Three allocations, then nothing can fail: ownership moves from the builder to the asset.
    prim *prims = c_copy(b.prims);
    material *mats = nullptr;
    image_rgba8 *imgs = nullptr;
    try {
        mats = c_copy(b.materials);
        imgs = c_copy(b.images);
    } catch (...) {
        free(prims);
        free(mats);
        throw;
    }
    a.prims = prims;
    a.prim_count = (int)b.prims.size();
    a.materials = mats;
    a.material_count = (int)b.materials.size();
    a.images = imgs;
    a.image_count = (int)b.images.size();
    b.prims.clear();
    b.images.clear();
    asset_compute_bounds(&a);
    if (!wline.empty())
        log_warn("%s: %s", path, wline.c_str());
    log_info("GLTF: [%s] %d prims, %d materials, %d images", a.name, a.prim_count, a.material_count,
             a.image_count);
    *out = a;
    return FS_OK;
}

} // namespace

extern "C" fs_status gltf_set_asset_root(const char *dir)
{
    g_asset_root.clear();
    if (!dir)
        return FS_OK;
    char real[PATH_MAX];
    struct stat sb;
    const char *why = !realpath(dir, real) || stat(real, &sb) != 0 ? strerror(errno)
                      : !S_ISDIR(sb.st_mode)                      ? "not a folder"
                                                                  : nullptr;
    if (why) {
        log_error("--asset-root: expected a folder, got '%s' (%s)", dir, why);
        return FS_ERR_USAGE;
    }
    g_asset_root = real;
    return FS_OK;
}

extern "C" void gltf_set_pixel_budget(uint64_t per_image, uint64_t per_scene)
{
    g_image_budget = per_image ? per_image : GLTF_DEFAULT_IMAGE_PIXELS;
    g_scene_budget = per_scene ? per_scene : GLTF_DEFAULT_SCENE_PIXELS;
}

extern "C" void gltf_begin_scene(void) { g_scene_pixels = 0; }

extern "C" fs_status gltf_load(const char *path, asset *out)
{
    FS_ASSERT(path && out);
    if (!out)
        return FS_ERR_INTERNAL;
    memset(out, 0, sizeof *out);
    if (!path)
        return FS_ERR_INTERNAL;
    try {
        return load(path, out);
    } catch (const load_error &e) {
        log_error("%s: %s", path, first_line(e.msg).c_str());
        return e.status;
    } catch (const std::bad_alloc &) {
        log_error("%s: out of memory", path);
        return FS_ERR_NOMEM;
    } catch (const std::exception &e) {
        log_error("%s: %s", path, first_line(e.what()).c_str());
        return FS_ERR_ASSET;
    } catch (...) {
        log_error("%s: unexpected C++ exception while loading", path);
        return FS_ERR_ASSET;
    }
}
