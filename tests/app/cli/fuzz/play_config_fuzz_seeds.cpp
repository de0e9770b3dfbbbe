// Writes the seed corpus of play_config_fuzz into the folder given as argument: config files
// (every key with a value of its type, wrong types, unknown keys, TOML syntax errors, numbers at
// the edges), each prefixed with the fuzz target's selector byte.
#include "support/text_seeds.h"

namespace {

const depthtouch::testing::TextSeed kSeeds[] = {
    {"every-key", 0,
     "display = \"kms\"\ndisplay-options = \"\"\nhaptic = \"falcon\"\nhaptic-options = "
     "\"intent=press\"\n"
     "decoder = \"ffmpeg\"\ndecoder-options = \"pool=24\"\nsource = \"ffmpeg\"\nremote = "
     "\"evdev\"\n"
     "remote-options = \"device=/dev/input/event3\"\nstereo = \"sbs\"\nstiffness = 1000.0\n"
     "rate = 1000\nreengage = \"ramp\"\nloop = true\nduration = 3.5\nsnapshot-dir = \"snaps\"\n"
     "snapshot-every = 30\nforce-log = \"f.csv\"\nstats = \"s.json\"\nrecord = \"r.mkv\"\n"
     "record-crf = 20\ncontrol = \"/run/dt.sock\"\nsize = \"1920x1080\"\nmesh-step = 2\n"
     "require-rt = false\nidle = true\nquiet = true\nverbose = false\nosd-seconds = 4\n"
     "lod-target = 0.9\nmax-lateness = 0.1\n"},
    {"given", static_cast<char>(0xff), "display = \"kms\"\nhaptic = \"sim\"\nstiffness = 900\n"},
    {"wrong-type", 0, "stiffness = \"hard\"\n"},
    {"wrong-type-given", static_cast<char>(0xff), "loop = 3\n"},
    {"unknown", 0, "stifness = 900\n"},
    {"edges", 0,
     "record-crf = 9223372036854775807\nmesh-step = -1\nsnapshot-every = 0\nrate = inf\n"
     "stiffness = nan\nduration = -0.0\nosd-seconds = 1e308\n"},
    {"syntax", 0, "display = \"unterminated\n[table]\nx = [1, 2\n"},
    {"nested", 0, "a = { b = { c = [[1], [2, [3]]] } }\n[t.u.v]\nw = 1970-01-01T00:00:00Z\n"},
    {"strings", 0,
     "display = '''multi\nline'''\ncontrol = \"\\u00e9\\t\\\"\"\nhaptic = \"\"\"x\ny\"\"\"\n"},
};

} // namespace

int main(int argc, char **argv)
{
    return depthtouch::testing::writeTextSeeds(argc, argv, "play_config_fuzz_seeds", kSeeds);
}
