#!/usr/bin/python3
"""A synthetic wall portfolio for `rockwatch study --walls` benchmarks (docs/BENCHMARKS.md, "Scale: portfolios,
shards, MPI"): N walls drawn with a fixed seed from the design paper's parametric range: b 0.10-0.21 m, storey height
2.6-4.0 m split evenly into h1 and h2, density 1700-1900 kg/m3, overburden 0 (half the walls) or 1-6 kN/m with
eccentricities 0-1.

    tests/bench/portfolio_walls.py 1000 > walls1000.csv
"""
import random
import sys


def main():
    n = int(sys.argv[1])
    rng = random.Random(18)
    print("id,b,h1,h2,rho,fp,a,a_prime")
    for i in range(n):
        b = rng.choice((0.10, 0.12, 0.14, 0.21))
        h = round(rng.uniform(2.6, 4.0), 2)
        rho = round(rng.uniform(1700, 1900))
        if rng.random() < 0.5:
            fp, a, a_prime = "", "", ""
        else:
            fp = round(rng.uniform(1000, 6000))
            a = round(rng.uniform(0, 1), 2)
            a_prime = round(rng.uniform(0, 1), 2)
        print("w%04d,%g,%g,%g,%d,%s,%s,%s" % (i, b, h / 2, h / 2, rho, fp, a, a_prime))


if __name__ == "__main__":
    main()
