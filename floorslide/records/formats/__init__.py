"""floorslide's own record formats, registered as ObsPy waveform plugins (entry points
``obspy.plugin.waveform``): ``AT2`` (PEER NGA), ``COSMOSV2`` (COSMOS V1/V2), ``FSTEXT`` (plain
text). Each module has ObsPy's ``_is_<format>(filename)`` and ``_read_<format>(filename, ...)``.
"""
