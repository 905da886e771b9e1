# pbf_render: see issue 4 (renderer helper fills this)
