#pragma once
// GLSL ES 3.00 sources of the synthetic scenes: one lit program (Blinn-Phong with a warm key
// light, a cool fill, ambient and rim, wrap lighting on skin; procedural textures per material)
// and the pass that turns the Z-buffer into 16-bit nearness.

namespace depthtouch::synthetic::shaders {

inline constexpr const char *kLitVertex = R"(#version 300 es
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat3 uNormalMatrix;
out vec3 vWorld;
out vec3 vNormal;
out vec3 vObject;
void main()
{
    vec4 world = uModel * vec4(aPosition, 1.0);
    vWorld = world.xyz;
    vNormal = uNormalMatrix * aNormal;
    vObject = aPosition;
    gl_Position = uViewProj * world;
}
)";

// Materials: 0 skin (head frame, metres), 1 cloth, 2 marble, 3 paint, 4 wood, 5 plaster,
// 6 rubber, 7 bust (skin neck, knitted sweater below). With uHaptic = 1 the program writes each
// surface point's haptic material codes instead of its colour (depthtouch/scene/material.h: R
// stiffness scale · 64, G static friction · 100, B dynamic friction · 100, as code / 255): the
// material track of the built-in content (docs/materials.md).
inline constexpr const char *kLitFragment = R"(#version 300 es
precision highp float;
in vec3 vWorld;
in vec3 vNormal;
in vec3 vObject;
uniform int uMaterial;
uniform int uHaptic;
uniform vec3 uTint;
uniform vec3 uEye;
uniform vec3 uKeyPosition;
uniform vec3 uKeyColor;
uniform vec3 uFillDirection;
uniform vec3 uFillColor;
uniform vec3 uAmbient;
uniform highp sampler3D uNoise;
out vec4 fragColor;

// Value noise from a 32³ texture of random bytes (trilinear, repeating): one fetch per octave,
// four independent channels.
float hash(vec3 p)
{
    return texture(uNoise, (floor(p) + 0.5) / 32.0).r;
}
vec4 noise4(vec3 x) { return texture(uNoise, x / 32.0); }
float noise(vec3 x) { return noise4(x).r; }
float fbm(vec3 p)
{
    return 0.5 * noise(p) + 0.25 * noise(p * 2.03 + vec3(1.7, 9.2, 3.1)) +
           0.125 * noise(p * 4.09 + vec3(5.3, 2.9, 7.7));
}
vec3 lin(vec3 srgb) { return pow(srgb, vec3(2.2)); }
// Tilts the normal by a noise gradient: fine surface relief without geometry.
vec3 bumped(vec3 n, vec3 p, float strength)
{
    vec3 g = noise4(p).gba;
    return normalize(n + strength * (g - 0.5));
}
float ellipse(vec2 d, vec2 r) { return dot(d / r, d / r); }

vec3 skinBase(vec3 q, inout vec3 n, inout float spec, inout float shininess, inout float wrap)
{
    n = bumped(n, q * 2200.0, 0.12); // pores
    spec = 0.18;
    shininess = 24.0;
    wrap = 0.35;
    return lin(vec3(0.86, 0.64, 0.53)) * (0.88 + 0.24 * fbm(q * 160.0));
}

vec3 skin(vec3 q, inout vec3 n, inout float spec, inout float shininess, inout float wrap)
{
    vec3 c = skinBase(q, n, spec, shininess, wrap);
    float front = smoothstep(0.03, 0.06, q.z);
    // blush on the cheeks
    vec2 cheek = vec2(abs(q.x) - 0.045, q.y + 0.012);
    c = mix(c, lin(vec3(0.86, 0.46, 0.42)), 0.35 * front * exp(-ellipse(cheek, vec2(0.02, 0.018))));
    // lips
    float lips = (1.0 - smoothstep(0.55, 1.0, ellipse(vec2(q.x, q.y + 0.0465), vec2(0.019, 0.0095))))
                 * front;
    c = mix(c, lin(vec3(0.72, 0.31, 0.33)), 0.85 * lips);
    spec = mix(spec, 0.45, lips);
    // brows, arched
    float bx = abs(q.x) - 0.030;
    float browY = q.y - 0.0345 + 18.0 * bx * bx;
    float brow = (1.0 - smoothstep(0.5, 1.0, ellipse(vec2(bx, browY), vec2(0.017, 0.0035)))) * front;
    c = mix(c, lin(vec3(0.25, 0.16, 0.10)) * (0.7 + 0.6 * noise(vec3(q.x * 900.0, q.y * 3000.0, 0.0))),
            0.9 * brow);
    // eyes: sclera, iris, pupil, and a lid shadow
    vec2 e = vec2(abs(q.x) - 0.030, q.y - 0.016);
    float sclera = (1.0 - smoothstep(0.8, 1.0, ellipse(e, vec2(0.0115, 0.0055)))) * front;
    float r = length(e);
    vec3 eye = mix(lin(vec3(0.92, 0.90, 0.86)), lin(vec3(0.28, 0.38, 0.22)) *
                   (0.7 + 0.5 * noise(vec3(atan(e.y, e.x) * 8.0, r * 900.0, 0.0))),
                   1.0 - smoothstep(0.0044, 0.0050, r));
    eye = mix(eye, vec3(0.01), 1.0 - smoothstep(0.0020, 0.0024, r));
    eye *= 0.55 + 0.45 * smoothstep(0.0055, 0.001, e.y);
    c = mix(c, eye, sclera);
    spec = mix(spec, 0.9, sclera);
    shininess = mix(shininess, 90.0, sclera);
    wrap = mix(wrap, 0.0, sclera);
    // hair: a cap whose line runs high on the forehead and low on the nape
    vec3 d = normalize(q / vec3(0.075, 0.10, 0.09));
    float line = mix(0.52, -0.35, smoothstep(0.15, -0.55, d.z));
    float hair = smoothstep(line - 0.02, line + 0.03, d.y + 0.03 * noise(q * 300.0));
    float strands = noise(vec3(q.x * 700.0, q.y * 40.0, q.z * 700.0));
    c = mix(c, lin(vec3(0.24, 0.15, 0.09)) * (0.55 + 0.8 * strands), hair);
    n = normalize(mix(n, bumped(n, vec3(q.x * 700.0, q.y * 40.0, q.z * 700.0), 0.6), hair));
    spec = mix(spec, 0.3, hair);
    shininess = mix(shininess, 40.0, hair);
    wrap = mix(wrap, 0.1, hair);
    return c;
}

vec3 cloth(vec3 p, vec3 tint, inout vec3 n)
{
    float threads = 650.0;
    float wx = sin(p.x * threads);
    float wy = sin(p.y * threads);
    float over = step(0.0, sin(p.x * threads * 0.5) * sin(p.y * threads * 0.5));
    float weave = 0.75 + 0.25 * mix(wx * wx, wy * wy, over);
    n = bumped(n, p * 400.0, 0.25);
    return tint * weave * (0.8 + 0.4 * fbm(p * 9.0));
}

// Haptic material codes (stiffness scale · 64, μs · 100, μd · 100) of a surface point.
vec3 hapticCodes(vec3 p)
{
    if (uMaterial == 0 || uMaterial == 7) {
        // Skin: soft cheeks and lips, a firm forehead (bone under it), slippery eyes, soft hair;
        // on the bust the sweater below the neckline is cloth.
        vec3 codes = vec3(54.0, 60.0, 45.0);
        if (uMaterial == 7) {
            float neckline = 1.0 - step(-0.095, p.y - 1.5 * p.x * p.x);
            return mix(codes, vec3(45.0, 80.0, 60.0), neckline);
        }
        float front = step(0.04, p.z);
        vec2 cheek = vec2(abs(p.x) - 0.045, p.y + 0.012);
        if (front > 0.5 && ellipse(cheek, vec2(0.024, 0.022)) < 1.0)
            codes = vec3(40.0, 70.0, 55.0);
        if (front > 0.5 && ellipse(vec2(p.x, p.y + 0.0465), vec2(0.019, 0.0095)) < 1.0)
            codes = vec3(36.0, 90.0, 70.0);
        if (front > 0.5 && abs(p.x) < 0.05 && p.y > 0.04)
            codes = vec3(96.0, 50.0, 38.0);
        vec2 e = vec2(abs(p.x) - 0.030, p.y - 0.016);
        if (front > 0.5 && ellipse(e, vec2(0.0115, 0.0055)) < 1.0)
            codes = vec3(64.0, 5.0, 3.0);
        vec3 d = normalize(p / vec3(0.075, 0.10, 0.09));
        float line = mix(0.52, -0.35, smoothstep(0.15, -0.55, d.z));
        if (d.y > line + 0.005)
            codes = vec3(32.0, 35.0, 25.0);
        return codes;
    }
    if (uMaterial == 1)
        return vec3(42.0, 85.0, 65.0); // the curtain's cloth: soft, grips the finger
    if (uMaterial == 2)
        return vec3(160.0, 12.0, 8.0); // marble: hard, slippery
    if (uMaterial == 3)
        return vec3(128.0, 30.0, 22.0); // painted
    if (uMaterial == 4)
        return vec3(144.0, 45.0, 35.0); // wood
    if (uMaterial == 5)
        return vec3(176.0, 60.0, 45.0); // plaster
    return vec3(45.0, 110.0, 90.0);     // rubber
}

void main()
{
    if (uHaptic == 1) {
        fragColor = vec4(hapticCodes(vObject) / 255.0, 1.0);
        return;
    }
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing)
        n = -n;
    float spec = 0.1;
    float shininess = 16.0;
    float wrap = 0.0;
    vec3 albedo = uTint;
    vec3 p = vObject;
    if (uMaterial == 0) {
        albedo = skin(p, n, spec, shininess, wrap);
    } else if (uMaterial == 1) {
        albedo = cloth(p, uTint, n);
        spec = 0.04;
    } else if (uMaterial == 2) {
        float v = sin((p.x + 0.6 * p.y + 0.3 * p.z) * 7.0 + 6.0 * fbm(p * 2.5));
        float vein = pow(1.0 - abs(v), 8.0);
        albedo = mix(uTint * (0.9 + 0.1 * fbm(p * 20.0)), lin(vec3(0.25, 0.25, 0.28)), 0.75 * vein);
        spec = 0.6;
        shininess = 80.0;
    } else if (uMaterial == 3) {
        albedo = uTint * (0.85 + 0.25 * fbm(p * 6.0)) * (0.95 + 0.1 * noise(p * 180.0));
        n = bumped(n, p * 60.0, 0.05);
        spec = 0.5;
        shininess = 60.0;
    } else if (uMaterial == 4) {
        float plank = floor(p.x / 0.14);
        float h = hash(vec3(plank, 3.0, 7.0));
        float along = p.z + h * 5.0;
        float grain = fract(along * 1.5 + 0.12 * sin(p.x * 60.0 + h * 6.0) +
                            0.7 * fbm(vec3(p.x * 25.0, along * 2.0, plank)));
        albedo = mix(lin(vec3(0.62, 0.42, 0.25)), lin(vec3(0.38, 0.23, 0.12)),
                     smoothstep(0.3, 0.9, grain)) * (0.85 + 0.3 * h);
        float gap = smoothstep(0.0, 0.004, abs(fract(p.x / 0.14 + 0.5) - 0.5) * 0.14);
        albedo *= 0.35 + 0.65 * gap;
        spec = 0.35;
        shininess = 40.0;
    } else if (uMaterial == 5) {
        albedo = uTint * (0.88 + 0.2 * fbm(p * 12.0));
        n = bumped(n, p * 250.0, 0.15);
        spec = 0.03;
    } else if (uMaterial == 6) {
        albedo = uTint * (0.9 + 0.15 * noise(p * 40.0));
        n = bumped(n, p * 90.0, 0.3);
        spec = 0.12;
        shininess = 10.0;
    } else {
        float neckline = 1.0 - smoothstep(-0.10, -0.09, p.y - 1.5 * p.x * p.x);
        vec3 nc = n;
        albedo = mix(skinBase(p, n, spec, shininess, wrap), cloth(p * 0.6, uTint, nc), neckline);
        n = normalize(mix(n, nc, neckline));
        spec = mix(spec, 0.04, neckline);
        wrap = mix(wrap, 0.0, neckline);
    }

    vec3 v = normalize(uEye - vWorld);
    vec3 l = uKeyPosition - vWorld;
    float dist2 = dot(l, l);
    l = normalize(l);
    float key = max((dot(n, l) + wrap) / (1.0 + wrap), 0.0) / (0.6 + 0.8 * dist2);
    float fill = max((dot(n, normalize(uFillDirection)) + wrap) / (1.0 + wrap), 0.0);
    vec3 h = normalize(l + v);
    float s = spec * pow(max(dot(n, h), 0.0), shininess) * step(0.0, dot(n, l));
    float rim = 0.12 * pow(1.0 - max(dot(n, v), 0.0), 3.0);
    vec3 color = albedo * (uAmbient + uKeyColor * key + uFillColor * fill + rim) + uKeyColor * s;
    fragColor = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

inline constexpr const char *kQuadVertex = R"(#version 300 es
out vec2 vUv;
void main()
{
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    vUv = 0.5 * p + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

// Window depth → metric distance Z (perspective camera with clip planes uNear, uFar) → nearness
// v = (1/Z − 1/far)/(1/near − 1/far), stored as 16 bits: high byte in red, low byte in green.
inline constexpr const char *kNearnessFragment = R"(#version 300 es
precision highp float;
in vec2 vUv;
uniform highp sampler2D uDepth;
uniform float uNear;
uniform float uFar;
out vec4 fragColor;
void main()
{
    float zw = texture(uDepth, vUv).r;
    float zn = 2.0 * zw - 1.0;
    float z = 2.0 * uNear * uFar / (uFar + uNear - zn * (uFar - uNear));
    float v = clamp((1.0 / z - 1.0 / uFar) / (1.0 / uNear - 1.0 / uFar), 0.0, 1.0);
    float q = floor(v * 65535.0 + 0.5);
    float hi = floor(q / 256.0);
    fragColor = vec4(hi / 255.0, (q - hi * 256.0) / 255.0, 0.0, 1.0);
}
)";

} // namespace depthtouch::synthetic::shaders
