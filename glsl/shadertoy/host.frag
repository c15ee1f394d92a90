#version 330 core
// Shadertoy's inputs around a user's mainImage (facet.lab.shadertoy fills them). The
// user's code (and common file) is included at the marker line below; fragCoord has its
// origin at the bottom-left pixel corner, as on Shadertoy. Each channel's sampler type
// (sampler2D, samplerCube for cube maps and the Cube A pass, sampler3D for volumes) comes as FACET_CHANNELn.
// With FACET_CUBE_PASS this is the Cube A pass: mainCubemap for face u_face (OpenGL's
// order +X, -X, +Y, -Y, +Z, -Z) with the ray through each texel centre.
// The wrapper's own names all start with facet_ so a user's #define cannot reach them.
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
uniform FACET_CHANNEL0 iChannel0;
uniform FACET_CHANNEL1 iChannel1;
uniform FACET_CHANNEL2 iChannel2;
uniform FACET_CHANNEL3 iChannel3;
#ifdef FACET_CUBE_PASS
uniform int facet_face;
#endif
// KDE shader wallpaper's desktop inputs, declared where a shader uses one it does not
// declare (facet.lab.dialect DESKTOP_INPUTS): a desktop of no windows, one screen and one
// virtual desktop.
#ifdef FACET_DECLARE_iMousePrev
uniform vec2 iMousePrev;            // the cursor a frame ago (headless: iMouse.xy)
#endif
#ifdef FACET_DECLARE_iWindowCount
uniform int iWindowCount;           // windows on the desktop: 0
#endif
#ifdef FACET_DECLARE_iWindowRects
uniform vec4 iWindowRects[16];      // (x, y, width, height) pixels, per window
#endif
#ifdef FACET_DECLARE_iWindowRectsPrev
uniform vec4 iWindowRectsPrev[16];
#endif
#ifdef FACET_DECLARE_iWindowVelocities
uniform vec2 iWindowVelocities[16]; // pixels per second, per window
#endif
#ifdef FACET_DECLARE_iScreenOffset
uniform vec2 iScreenOffset;
#endif
#ifdef FACET_DECLARE_iScreenIndex
uniform int iScreenIndex;
#endif
#ifdef FACET_DECLARE_iScreenCount
uniform int iScreenCount;
#endif
#ifdef FACET_DECLARE_iVirtualDesktop
uniform int iVirtualDesktop;
#endif
#ifdef FACET_DECLARE_iVirtualDesktopCount
uniform int iVirtualDesktopCount;   // 1
#endif
#ifdef FACET_DECLARE_iVirtualDesktopAnim
uniform float iVirtualDesktopAnim;
#endif
#ifdef FACET_GLOBAL_FRAG
// The KDE dialect's void mainImage() reads and writes these globals.
vec2 fragCoord;
vec4 fragColor;
#endif

out vec4 facet_FragColor;

FACET_USER_CODE

void main() {
    vec4 facet_color = vec4(0.0, 0.0, 0.0, 1.0);
#ifdef FACET_CUBE_PASS
    vec2 facet_c = gl_FragCoord.xy / iResolution.xy * 2.0 - 1.0;  // (sc, tc) of the texel
    vec3 facet_dirs[6] = vec3[6](vec3(1.0, -facet_c.y, -facet_c.x),
                                 vec3(-1.0, -facet_c.y, facet_c.x),
                                 vec3(facet_c.x, 1.0, facet_c.y),
                                 vec3(facet_c.x, -1.0, -facet_c.y),
                                 vec3(facet_c.x, -facet_c.y, 1.0),
                                 vec3(-facet_c.x, -facet_c.y, -1.0));
    mainCubemap(facet_color, gl_FragCoord.xy, vec3(0.0), normalize(facet_dirs[facet_face]));
#elif defined(FACET_GLOBAL_MAIN)
    fragCoord = gl_FragCoord.xy;
    fragColor = facet_color;
    mainImage();
    facet_color = fragColor;
#else
    mainImage(facet_color, gl_FragCoord.xy);
#endif
    facet_FragColor = facet_color;
}
