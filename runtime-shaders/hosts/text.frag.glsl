// BAKER_text: a distance-field atlas (BAKER_glyph_atlas) shaded with baker_text.glsl at "@baker:modules";
// premultiplied alpha out (blend ONE, ONE_MINUS_SRC_ALPHA).
// @baker:modules
in vec2 v_uv;
uniform sampler2D u_atlas;
uniform vec2 u_atlasSize;
uniform float u_distanceRange;
uniform int u_fieldType;
uniform BakerTextStyle u_style;
out vec4 fragColor;
void main() {
    vec4 texel = texture(u_atlas, v_uv);
    float screenPxRange = baker_text_screen_px_range(u_distanceRange, u_atlasSize, fwidth(v_uv));
    fragColor = baker_text_shade(u_style, texel, texel, u_fieldType, u_distanceRange, screenPxRange);
}
