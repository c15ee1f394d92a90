#version 330 core
// Shadertoy's inputs around a user's mainImage (facet.lab.shadertoy fills them). The
// user's code (and common file) is included at the marker line below; fragCoord has its
// origin at the bottom-left pixel corner, as on Shadertoy.
uniform vec3 iResolution;           // viewport size in pixels (z = pixel aspect, 1)
uniform float iTime;                // seconds since the start
uniform float iTimeDelta;           // seconds per frame
uniform int iFrame;                 // frame number, from 0
uniform float iFrameRate;           // frames per second
uniform vec4 iMouse;                // xy: cursor while pressed; zw: click (signs as Shadertoy)
uniform vec4 iDate;                 // year, month (0-11), day, seconds since midnight
uniform float iSampleRate;          // 44100
uniform float iChannelTime[4];      // seconds, per channel
uniform vec3 iChannelResolution[4]; // pixels, per channel
uniform sampler2D iChannel0;
uniform sampler2D iChannel1;
uniform sampler2D iChannel2;
uniform sampler2D iChannel3;

out vec4 facet_FragColor;

FACET_USER_CODE

void main() {
    vec4 color = vec4(0.0, 0.0, 0.0, 1.0);
    mainImage(color, gl_FragCoord.xy);
    facet_FragColor = color;
}
