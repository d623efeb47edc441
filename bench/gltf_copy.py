"""Writing a modified copy of a glTF scene somewhere else: the benchmark helpers' shared part.

The copy's buffers, images and the environment recorded in `scenes[0].extras` point back to the
original files by relative paths, so it can be written anywhere on the same file system.
"""
import json
import os
import urllib.parse


def rebase_files(document, source, out):
    """Makes the relative file references of `document`, read from `source`, valid from `out`."""
    # From the copy's folder back to the original's, as a relative URI.
    back = os.path.relpath(os.path.dirname(os.path.abspath(source)),
                           os.path.dirname(os.path.abspath(out)))

    def rebase(uri):
        if uri.startswith("data:"):
            return uri
        return urllib.parse.quote(back) + "/" + uri

    for item in document.get("buffers", []) + document.get("images", []):
        if "uri" in item:
            item["uri"] = rebase(item["uri"])
    for environment in (document.get("scenes", [{}])[0].get("extras", {})
                        .get("mitsuba_environment", [])):
        environment["file"] = os.path.join(back, environment["file"])


def write_document(document, out):
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w") as f:
        json.dump(document, f)
