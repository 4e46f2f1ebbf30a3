#include "core/math.h"

namespace veach {

Transform operator*(const Transform& a, const Transform& b) {
    Transform r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            float v = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
            if (j == 3) v += a.m[i][3];
            r.m[i][j] = v;
        }
    }
    return r;
}

Transform inverse(const Transform& t) {
    // Computed in double: instance matrices with large translations or scales keep their
    // precision, which matters for the scale-invariance tests.
    double a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = t.m[i][j];
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    Transform r;
    if (det == 0.0 || !std::isfinite(det)) return r;
    double inv[3][3];
    inv[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    for (int i = 0; i < 3; ++i) {
        double tr = 0.0;
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = static_cast<float>(inv[i][j]);
            tr -= inv[i][j] * t.m[j][3];
        }
        r.m[i][3] = static_cast<float>(tr);
    }
    return r;
}

Transform translation(const Vec3& t) {
    Transform r;
    r.m[0][3] = t.x;
    r.m[1][3] = t.y;
    r.m[2][3] = t.z;
    return r;
}

Transform scaling(const Vec3& s) {
    Transform r;
    r.m[0][0] = s.x;
    r.m[1][1] = s.y;
    r.m[2][2] = s.z;
    return r;
}

Transform rotation_quaternion(float x, float y, float z, float w) {
    float n = std::sqrt(x * x + y * y + z * z + w * w);
    Transform r;
    if (!(n > 0.0f) || !std::isfinite(n)) return r;
    x /= n;
    y /= n;
    z /= n;
    w /= n;
    r.m[0][0] = 1 - 2 * (y * y + z * z);
    r.m[0][1] = 2 * (x * y - z * w);
    r.m[0][2] = 2 * (x * z + y * w);
    r.m[1][0] = 2 * (x * y + z * w);
    r.m[1][1] = 1 - 2 * (x * x + z * z);
    r.m[1][2] = 2 * (y * z - x * w);
    r.m[2][0] = 2 * (x * z - y * w);
    r.m[2][1] = 2 * (y * z + x * w);
    r.m[2][2] = 1 - 2 * (x * x + y * y);
    return r;
}

void normalise_quaternion(float* q) {
    double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
    if (!(n > 0) || !std::isfinite(n)) {
        q[0] = q[1] = q[2] = 0;
        q[3] = 1;
        return;
    }
    for (int i = 0; i < 4; ++i) q[i] = float(q[i] / n);
}

void slerp_quaternion(const float* a, const float* b_in, double s, float* out) {
    double b[4] = {b_in[0], b_in[1], b_in[2], b_in[3]};
    double d = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2] + double(a[3]) * b[3];
    if (d < 0) {
        d = -d;
        for (double& c : b) c = -c;
    }
    double wa = 1 - s, wb = s;
    if (d < 0.9995) {
        double theta = std::acos(std::min(d, 1.0));
        double sin_theta = std::sin(theta);
        wa = std::sin((1 - s) * theta) / sin_theta;
        wb = std::sin(s * theta) / sin_theta;
    }
    for (int i = 0; i < 4; ++i) out[i] = float(wa * a[i] + wb * b[i]);
    normalise_quaternion(out);
}

std::array<float, 4> quaternion_of_rotation(const Transform& r) {
    // Shepperd's method: from the largest of the four diagonal combinations, so no division by
    // a small number.
    const auto& a = r.m;
    const double tr = double(a[0][0]) + a[1][1] + a[2][2];
    double q[4];
    if (tr > 0) {
        double s = 2 * std::sqrt(1 + tr);
        q[3] = 0.25 * s;
        q[0] = (double(a[2][1]) - a[1][2]) / s;
        q[1] = (double(a[0][2]) - a[2][0]) / s;
        q[2] = (double(a[1][0]) - a[0][1]) / s;
    } else if (a[0][0] > a[1][1] && a[0][0] > a[2][2]) {
        double s = 2 * std::sqrt(std::max(0.0, 1 + double(a[0][0]) - a[1][1] - a[2][2]));
        q[3] = (double(a[2][1]) - a[1][2]) / s;
        q[0] = 0.25 * s;
        q[1] = (double(a[0][1]) + a[1][0]) / s;
        q[2] = (double(a[0][2]) + a[2][0]) / s;
    } else if (a[1][1] > a[2][2]) {
        double s = 2 * std::sqrt(std::max(0.0, 1 + double(a[1][1]) - a[0][0] - a[2][2]));
        q[3] = (double(a[0][2]) - a[2][0]) / s;
        q[0] = (double(a[0][1]) + a[1][0]) / s;
        q[1] = 0.25 * s;
        q[2] = (double(a[1][2]) + a[2][1]) / s;
    } else {
        double s = 2 * std::sqrt(std::max(0.0, 1 + double(a[2][2]) - a[0][0] - a[1][1]));
        q[3] = (double(a[1][0]) - a[0][1]) / s;
        q[0] = (double(a[0][2]) + a[2][0]) / s;
        q[1] = (double(a[1][2]) + a[2][1]) / s;
        q[2] = 0.25 * s;
    }
    std::array<float, 4> out{float(q[0]), float(q[1]), float(q[2]), float(q[3])};
    normalise_quaternion(out.data());
    return out;
}

Transform from_column_major(const double m[16]) {
    Transform r;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) r.m[row][col] = static_cast<float>(m[col * 4 + row]);
    return r;
}

}  // namespace veach
