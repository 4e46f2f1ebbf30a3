// The options table through the C API (libveach.so only): every option the device query
// "options" describes is what a fresh scene or render holds by default, takes its range's ends
// and reads them back, refuses one step beyond them (one line naming the option), and a string
// with a fixed list takes every name on it and nothing else. The command's side of the same
// promise (flags, defaults, ranges) is tests/output/check_cli_options.py.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "veach/veach.h"

namespace {

const std::string k_cornell = std::string(VEACH_EXAMPLES_DIR) + "/cornell/cornell.gltf";

std::string device_string(VeachDevice d, const char* name) {
    size_t length = 0;
    EXPECT_EQ(veachGetDeviceString(d, name, nullptr, 0, &length), VEACH_ERROR_NONE) << veachGetLastError();
    std::string s(length + 1, '\0');
    veachGetDeviceString(d, name, s.data(), s.size(), &length);
    s.resize(length);
    return s;
}

// One object's options through its six entry points.
struct Target {
    VeachScene scene = nullptr;    // a scene option's (not loaded)
    VeachRender render = nullptr;  // a render option's
    VeachError set_int(const char* n, long long v) {
        return scene ? veachSetSceneInt(scene, n, v) : veachSetInt(render, n, v);
    }
    VeachError set_float(const char* n, double v) {
        return scene ? veachSetSceneFloat(scene, n, v) : veachSetFloat(render, n, v);
    }
    VeachError set_string(const char* n, const std::string& v) {
        return scene ? veachSetSceneString(scene, n, v.c_str()) : veachSetString(render, n, v.c_str());
    }
    long long get_int(const char* n) {
        long long v = -12345;
        EXPECT_EQ(scene ? veachGetSceneInt(scene, n, &v) : veachGetInt(render, n, &v), VEACH_ERROR_NONE) << n;
        return v;
    }
    double get_float(const char* n) {
        double v = -12345;
        EXPECT_EQ(scene ? veachGetSceneFloat(scene, n, &v) : veachGetFloat(render, n, &v), VEACH_ERROR_NONE) << n;
        return v;
    }
    std::string get_string(const char* n) {
        char buffer[256] = {0};
        size_t length = 0;
        EXPECT_EQ(scene ? veachGetSceneString(scene, n, buffer, sizeof(buffer), &length)
                        : veachGetString(render, n, buffer, sizeof(buffer), &length),
                  VEACH_ERROR_NONE)
            << n;
        return buffer;
    }
};

#define EXPECT_REFUSED_NAMING(call, name)                                                                       \
    do {                                                                                                        \
        EXPECT_EQ((call), VEACH_ERROR_INVALID_ARGUMENT) << name;                                                \
        EXPECT_NE(std::string(veachGetLastError()).find(name), std::string::npos) << veachGetLastError();       \
        EXPECT_EQ(std::string(veachGetLastError()).find('\n'), std::string::npos) << veachGetLastError();       \
    } while (0)

TEST(OptionTable, EveryOptionHasItsDefaultTakesItsRangeAndRefusesBeyondIt) {
    VeachDevice device = veachNewDevice();
    const nlohmann::json table = nlohmann::json::parse(device_string(device, "options"));
    ASSERT_GT(table.size(), 30u);
    VeachScene cornell = veachNewSceneFromFile(device, k_cornell.c_str());
    ASSERT_NE(cornell, nullptr) << veachGetLastError();
    int checked = 0;
    for (const nlohmann::json& row : table) {
        const std::string name = row.at("name");
        const char* n = name.c_str();
        const bool is_scene = row.at("object") == "scene";
        // A fresh object per option: options that exclude each other (env_map, env_color) or
        // imply another (passes turns aovs on) never meet.
        auto fresh = [&] {
            Target t;
            if (is_scene)
                t.scene = veachNewScene(device);
            else
                t.render = veachNewRender(cornell);
            return t;
        };
        auto release = [](Target& t) {
            veachReleaseScene(t.scene);
            veachReleaseRender(t.render);
        };
        Target t = fresh();
        const std::string type = row.at("type");
        SCOPED_TRACE(name);
        if (type == "int") {
            const long long lo = row.at("min"), hi = row.at("max");
            EXPECT_EQ(t.get_int(n), row.at("default").get<long long>());
            EXPECT_EQ(t.set_int(n, lo), VEACH_ERROR_NONE) << veachGetLastError();
            EXPECT_EQ(t.get_int(n), lo);
            EXPECT_EQ(t.set_int(n, hi), VEACH_ERROR_NONE) << veachGetLastError();
            EXPECT_EQ(t.get_int(n), hi);
            if (lo > std::numeric_limits<long long>::min()) EXPECT_REFUSED_NAMING(t.set_int(n, lo - 1), name);
            if (hi < std::numeric_limits<long long>::max()) EXPECT_REFUSED_NAMING(t.set_int(n, hi + 1), name);
            EXPECT_REFUSED_NAMING(t.set_float(n, 1.0), name);  // the type is the name's
        } else if (type == "float") {
            const double lo = row.at("min"), hi = row.at("max");
            if (row.at("default").is_null())
                EXPECT_TRUE(std::isnan(t.get_float(n)));
            else
                EXPECT_EQ(t.get_float(n), row.at("default").get<double>());
            // Stored as float or double: the ends read back within a float's rounding.
            EXPECT_EQ(t.set_float(n, lo), VEACH_ERROR_NONE) << veachGetLastError();
            EXPECT_NEAR(t.get_float(n), lo, std::abs(lo) * 1e-7);
            EXPECT_EQ(t.set_float(n, hi), VEACH_ERROR_NONE) << veachGetLastError();
            EXPECT_NEAR(t.get_float(n), hi, std::abs(hi) * 1e-7);
            EXPECT_REFUSED_NAMING(t.set_float(n, lo - std::max(1e-3, std::abs(lo) * 1e-3)), name);
            EXPECT_REFUSED_NAMING(t.set_float(n, hi + std::max(1e-3, std::abs(hi) * 1e-3)), name);
            EXPECT_REFUSED_NAMING(t.set_float(n, std::nan("")), name);
            EXPECT_REFUSED_NAMING(t.set_int(n, 1), name);
        } else {
            EXPECT_EQ(t.get_string(n), row.at("default").get<std::string>());
            if (row.contains("choices")) {
                for (const std::string choice : row.at("choices")) {
                    EXPECT_EQ(t.set_string(n, choice), VEACH_ERROR_NONE) << veachGetLastError();
                    EXPECT_EQ(t.get_string(n), choice);
                }
                EXPECT_REFUSED_NAMING(t.set_string(n, "no-such-name"), name);
            }
            EXPECT_REFUSED_NAMING(t.set_int(n, 1), name);
        }
        release(t);
        ++checked;
    }
    EXPECT_EQ(checked, static_cast<int>(table.size()));
    veachReleaseScene(cornell);
    veachReleaseDevice(device);
}

TEST(OptionTable, LibraryMessagesNameOptionsNotFlags) {
    VeachDevice device = veachNewDevice();
    VeachScene cornell = veachNewSceneFromFile(device, k_cornell.c_str());
    VeachRender r = veachNewRender(cornell);
    EXPECT_EQ(veachSetInt(r, "spp", 0), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(veachGetLastError(), "spp must be at least 1");
    veachSetInt(r, "width", 8);
    veachSetInt(r, "spp", 4);
    veachSetInt(r, "sample_end", 8);  // past spp: found when the render starts
    EXPECT_EQ(veachRender(r), VEACH_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(std::string(veachGetLastError()).find("--"), std::string::npos) << veachGetLastError();
    EXPECT_NE(std::string(veachGetLastError()).find("spp"), std::string::npos) << veachGetLastError();
    veachReleaseRender(r);
    veachReleaseScene(cornell);
    veachReleaseDevice(device);
}

}  // namespace
