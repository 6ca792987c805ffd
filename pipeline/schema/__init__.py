"""The file formats: bearing, profile and sweep TOML files, units, shipped files.

The schema of every input field is :data:`pipeline.schema.fields.FIELDS`.

- :mod:`~pipeline.schema.config`: the bearing and profile formats, described; their readers' names;
- :mod:`~pipeline.schema.fields`: the schema: every input field's kind, bounds, default, unit;
- :mod:`~pipeline.schema.tomlfile`: reading TOML, key paths, ``--set`` values, overrides;
- :mod:`~pipeline.schema.reader`: reading one TOML table against the schema;
- :mod:`~pipeline.schema.convert`: the loader's one converter, a file's tables into dataclasses;
- :mod:`~pipeline.schema.bearingfile`: bearing files into :class:`rvcore.bearing.geometry.Bearing`;
- :mod:`~pipeline.schema.profilefile`: profile files into :class:`rvcore.profile.Profile`;
- :mod:`~pipeline.schema.sweepfile`: sweep files expanded into resolved cases (:func:`read_sweep_file`);
- :mod:`~pipeline.schema.sweepaxes`: a sweep file's axes, fixed and listed values, sensors;
- :mod:`~pipeline.schema.resolver`: a sweep's bearing and profile with each case's overrides;
- :mod:`~pipeline.schema.caseids`: canonical JSON of a configuration and its hash (case ids);
- :mod:`~pipeline.schema.stored`: a stored configuration read back into dataclasses;
- :mod:`~pipeline.schema.units`: quantities parsed with pint; UDUNITS spellings for the files;
- :mod:`~pipeline.schema.parameters`: the report's table of every input value;
- :mod:`~pipeline.schema.reference`: reference fit files (``sweeps/reference/*.toml``);
- :mod:`~pipeline.schema.shipped`: where the shipped sweeps, bearings and profiles live.
"""
from ..exports import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    ".config": ("apply_override", "bearing_from_dict", "load_bearing", "load_profile", "lookup", "parse_set",
                "parse_sets", "parse_value", "profile_from_dict", "read_toml", "resolve_path"),
    ".fields": ("FIELDS", "REQUIRED", "Field", "check_set_key"),
    ".parameters": ("ParameterRow", "parameter_table"),
    ".sweepfile": ("MODEL_VERSION", "OPERATING_POINT", "REALIZATION", "CaseSpec", "Sweep", "read_sweep_file",
                   "sweep_from_dict"),
    ".units": ("SI_UNITS", "compose_units", "format_quantity", "parse_quantity", "registry", "si_udunits",
               "udunits"),
    ".stored": ("StoredConfiguration", "stored_configuration"),
})
