// Writes the seed corpus of control_line_fuzz into the folder given as argument: sessions of
// control lines in the JSON and text forms (every command, queries, request ids, refusals,
// malformed JSON, numbers beyond a double, mpv's verbs), each prefixed with the fuzz target's
// selector byte.
#include "support/text_seeds.h"

namespace {

const depthtouch::testing::TextSeed kSeeds[] = {
    {"json-session", 0,
     "{\"command\":[\"play\"],\"request_id\":1}\n{\"command\":[\"pause\"]}\n"
     "{\"command\":[\"seek\",10,\"absolute\"],\"request_id\":\"a\"}\n"
     "{\"command\":[\"seek\",-2.5]}\n{\"command\":[\"stereo-mode\",\"tab\"]}\n"
     "{\"command\":[\"haptics\",false]}\n{\"command\":[\"stiffness\",1200]}\n"
     "{\"command\":[\"get\",\"state\"]}\n{\"command\":[\"loop\",true]}\n"
     "{\"command\":[\"recenter\"]}\n{\"command\":[\"stop\"]}\n"
     "{\"command\":[\"play\",\"other.mkv\"]}\n{\"command\":[\"quit\"]}\n"},
    {"text-session", 0,
     "play\ntoggle-pause\nseek -10\nseek 5 abs\nnext-stereo-mode\nstereo-mode anaglyph\n"
     "haptics toggle\nstiffness +\nstiffness -\nget stiffness\nget url\nget error\n"
     "loop off\nrecenter\nplay 'my file.mkv'\nstop\nplay \"udp://127.0.0.1:5000\"\nquit\n"},
    {"refusals", 0,
     "pause\nseek 1e400\n{\"command\":[\"seek\",1e400]}\n"
     "{\"command\":[\"get\",\"state\"],\"request_id\":1e999}\n"
     "{\"command\":[\"stiffness\",1e309]}\n{\"command\":[]}\n{\"command\":\"pause\"}\n"
     "{\"command\":[1,2]}\n{\"command\":[\"seek\",{\"x\":1}]}\n{\"request_id\":1}\n"
     "{\"command\":[\"seek\",10]\n[1,2]\n   \n\tget   state\t\nexplode now\nplay 'unterminated\n"},
    {"mpv-session", 0,
     "{\"command\":[\"play\"]}\n"
     "{\"command\":[\"get_property\",\"time-pos\"],\"request_id\":1}\n"
     "{\"command\":[\"get_property_string\",\"pause\"]}\n"
     "{\"command\":[\"set_property\",\"pause\",true]}\n"
     "{\"command\":[\"set_property_string\",\"stiffness\",\"1e400\"]}\n"
     "{\"command\":[\"set_property\",\"percent-pos\",50]}\n"
     "{\"command\":[\"cycle\",\"stereo-mode\"]}\n"
     "{\"command\":[\"add\",\"time-pos\",-10]}\n"
     "{\"command\":[\"keypress\",\"PLAYPAUSE\"]}\n"
     "{\"command\":[\"observe_property\",1,\"time-pos\"]}\n"
     "{\"command\":[\"unobserve_property\",1]}\n"
     "{\"command\":[\"get_property\",\"loop-file\"]}\n"
     "{\"command\":[\"set_property\",\"volume\",50]}\n"},
    {"failing-open", 0x11, "play\nget error\nplay\nstop\nplay x.mkv\nquit\n"},
    {"failing-seek", 0x06, "play\nseek 3\nget state\nplay\nstop\n"},
    {"opening", 0x20, "play\nstop\nplay fifo\nget state\nquit\n"},
};

} // namespace

int main(int argc, char **argv)
{
    return depthtouch::testing::writeTextSeeds(argc, argv, "control_line_fuzz_seeds", kSeeds);
}
