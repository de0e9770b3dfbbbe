// Writes the seed corpus of trajectory_fuzz into the folder given as argument: trajectory CSVs that
// parse (columns in any order, extra columns, CRLF, blank lines, limits) and ones that do not (bad
// numbers, times not increasing, a short row, huge values), written at run time (no committed
// corpus).
#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: trajectory_fuzz_seeds DIR\n");
        return 2;
    }
    static const char *const kSeeds[] = {
        "t,x,y,z\n0,0,0,0.01\n0.05,0.001,0.002,-0.013\n0.2,0.004,0.002,-0.013\n",
        "z, t,x,y,note\n0.01,0,0.001,0.002,a\r\n0.0,0.5,0.002,0.002,b\n\n",
        "t,x,y,z\n-1,0,0,0\n0,0,0,-0.02\n1.5,0.03,-0.03,-0.02\n",
        "t,x,y,z\n0,-100,100,-100\n1e6,100,-100,100\n",
        "t,x,y,z\n0,+1e-3,  2e-3 ,\t-0.0\n1,0,0,0\n",
        "t,x,y,z\n0,0,0,0\n0.1,1.7e308,0,0\n",
        "t,x,y,z\n0,0,0,0\n1e300,0,0,0\n",
        "t,x,y,z\n0,0,0,0\n0,1,1,1\n",
        "t,x,y,z\n0,0,0\n",
        "t,x,y,z\n0,nan,0,0\n",
        "t,x,y\n0,0,0\n",
        "",
    };
    int n = 0;
    for (const char *seed : kSeeds) {
        const std::string path = std::string(argv[1]) + "/seed-" + std::to_string(n++) + ".csv";
        std::ofstream out(path, std::ios::binary);
        out << seed;
        if (!out) {
            std::fprintf(stderr, "trajectory_fuzz_seeds: cannot write %s\n", path.c_str());
            return 1;
        }
    }
    return 0;
}
