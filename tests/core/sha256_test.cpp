// SHA-256 against the FIPS 180-4 example digests (NIST CSRC examples).
#include "harness/core/sha256.h"

#include <gtest/gtest.h>

using namespace pxh;

TEST(Sha256, FipsExamples) {
    EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256_hex("abc"),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, ChunkingDoesNotMatter) {
    std::string s;
    for (int i = 0; i < 1000; ++i) s += char(i * 37);
    for (size_t chunk : {1, 3, 63, 64, 65, 200}) {
        Sha256 h;
        for (size_t i = 0; i < s.size(); i += chunk)
            h.update(s.data() + i, std::min(chunk, s.size() - i));
        EXPECT_EQ(h.hex(), sha256_hex(s)) << chunk;
    }
}
