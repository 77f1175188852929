// gltf_bin.hpp - a glTF buffer as a list of pieces: ranges of the mesh's own arrays written as they are, and the few bytes the builder makes (C++ only, not installed).
#ifndef JETMESH_FORMATS_GLTF_BIN_HPP
#define JETMESH_FORMATS_GLTF_BIN_HPP

#include <cstddef>
#include <cstring>
#include <list>
#include <vector>

#include "gltf_wrap.h"

// The buffer's bytes are the pieces in order. A borrowed piece points into
// memory the caller keeps alive (the jm_mesh's arrays) until the bytes are
// written; an owned piece's bytes live in bytes or floats. Each append starts on a
// multiple of 4 (zero bytes before it) and returns that offset.
struct jmf_gltf_bin {
    std::vector<jmf_gltf_piece> pieces;
    std::list<std::vector<unsigned char>> bytes;
    std::list<std::vector<float>> floats;
    size_t size = 0; // the offset the next byte gets (it may start above 0)

    void pad4()
    {
        static const unsigned char zeros[4] = {0, 0, 0, 0};
        if (size % 4) push(zeros, 4 - size % 4);
    }
    size_t borrow(const void *src, size_t n)
    {
        pad4();
        const size_t off = size;
        if (n) push(src, n);
        return off;
    }
    // Keeps v (moved: its bytes do not move) and appends them.
    size_t own(std::vector<unsigned char> &&v)
    {
        bytes.push_back(std::move(v));
        return borrow(bytes.back().data(), bytes.back().size());
    }
    size_t own(std::vector<float> &&v)
    {
        floats.push_back(std::move(v));
        return borrow(floats.back().data(), floats.back().size() * sizeof(float));
    }
    // Appends the bytes to out, whose size was this buffer's starting size.
    void flatten(std::vector<unsigned char> &out) const
    {
        out.reserve(size);
        for (const jmf_gltf_piece &p : pieces) out.insert(out.end(), p.data, p.data + p.size);
    }

private:
    void push(const void *src, size_t n)
    {
        pieces.push_back(jmf_gltf_piece{static_cast<const unsigned char *>(src), n});
        size += n;
    }
};

#endif
