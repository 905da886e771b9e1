# pbf_bench, pbf_stress: see issue 5
