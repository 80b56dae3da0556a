/* The XDMF sidecar of a results file: a temporal collection of particle
 * clouds (Polyvertex grids) whose arrays live in the .h5 file, so ParaView
 * and VisIt open the run directly. Rewritten whole after every snapshot,
 * through a temporary file and a rename, so a reader never sees half of it. */
#include "core/core.h"
#include "io/io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The .h5 name goes into XML text: escape what XML reserves. */
static void put_escaped(FILE *out, const char *text)
{
    for (; *text; text++) {
        switch (*text) {
        case '&': fputs("&amp;", out); break;
        case '<': fputs("&lt;", out); break;
        case '>': fputs("&gt;", out); break;
        case '"': fputs("&quot;", out); break;
        case '\'': fputs("&apos;", out); break;
        default: fputc(*text, out);
        }
    }
}

static void put_item(FILE *out, const char *h5_name, size_t snapshot, const char *dataset,
                     size_t n, int vector, int integer)
{
    fprintf(out, "          <DataItem Dimensions=\"%zu%s\" NumberType=\"%s\" Precision=\"%d\" "
                 "Format=\"HDF\">", n, vector ? " 2" : "", integer ? "Int" : "Float",
            integer ? 4 : 8);
    put_escaped(out, h5_name);
    fprintf(out, ":/snapshots/%06zu/%s</DataItem>\n", snapshot, dataset);
}

static void put_attribute(FILE *out, const char *h5_name, size_t snapshot, const char *name,
                          size_t n, int vector, int integer)
{
    fprintf(out, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name,
            vector ? "Vector" : "Scalar");
    put_item(out, h5_name, snapshot, name, n, vector, integer);
    fputs("        </Attribute>\n", out);
}

static void put_document(FILE *out, const char *h5_name, size_t count, const double *times,
                         const size_t *particles)
{
    fputs("<?xml version=\"1.0\" ?>\n"
          "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
          "<Xdmf Version=\"3.0\">\n"
          "  <Domain>\n"
          "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          out);
    for (size_t k = 0; k < count; k++) {
        size_t n = particles[k];
        fprintf(out, "      <Grid Name=\"snapshot_%06zu\" GridType=\"Uniform\">\n", k);
        fprintf(out, "        <Time Value=\"%.17g\"/>\n", times[k]);
        /* Each particle a vertex cell, listed by /vertices: the Xdmf3 readers
         * and meshio make no cells from a topology without its connectivity. */
        fprintf(out, "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%zu\" "
                     "NodesPerElement=\"1\">\n", n);
        fprintf(out, "          <DataItem Dimensions=\"%zu 1\" NumberType=\"Int\" Precision=\"4\" "
                     "Format=\"HDF\">", n);
        put_escaped(out, h5_name);
        fputs(":/vertices</DataItem>\n        </Topology>\n", out);
        fputs("        <Geometry GeometryType=\"XY\">\n", out);
        put_item(out, h5_name, k, "position", n, 1, 0);
        fputs("        </Geometry>\n", out);
        put_attribute(out, h5_name, k, "velocity", n, 1, 0);
        put_attribute(out, h5_name, k, "pressure", n, 0, 0);
        put_attribute(out, h5_name, k, "number_density", n, 0, 0);
        put_attribute(out, h5_name, k, "kind", n, 0, 1);
        put_attribute(out, h5_name, k, "fluid_id", n, 0, 1);
        fputs("      </Grid>\n", out);
    }
    fputs("    </Grid>\n  </Domain>\n</Xdmf>\n", out);
}

int xdmf_write(const char *xdmf_path, const char *h5_name, size_t count, const double *times,
               const size_t *particles, char *handle_error)
{
    char reason[256] = "", *target;
    int refused = file_replace_target(xdmf_path, &target, reason, sizeof reason);
    if (refused != MPS2P_OK)
        return fail(handle_error, refused, "XDMF sidecar \"%s\": %s", xdmf_path, reason);
    char *temporary = path_join_suffix(target, strlen(target), ".tmp");
    if (!temporary) {
        free(target);
        return fail(handle_error, MPS2P_ERR_NOMEM, "out of memory writing \"%s\"", xdmf_path);
    }
    FILE *out = fopen(temporary, "w");
    if (!out) {
        describe_errno(errno, reason, sizeof reason);
        int status = fail(handle_error, MPS2P_ERR_IO, "XDMF sidecar \"%s\": cannot create: %s",
                          temporary, reason);
        free(temporary);
        free(target);
        return status;
    }
    put_document(out, h5_name, count, times, particles);
    int failed = ferror(out);
    if (fclose(out) != 0 || failed) {
        describe_errno(errno, reason, sizeof reason);
        remove(temporary);
        int status = fail(handle_error, MPS2P_ERR_IO, "XDMF sidecar \"%s\": cannot write: %s",
                          temporary, reason);
        free(temporary);
        free(target);
        return status;
    }
    int status = MPS2P_OK;
    if (file_replace(temporary, target, reason, sizeof reason) != 0)
        status = fail(handle_error, MPS2P_ERR_IO,
                      "XDMF sidecar \"%s\": cannot replace it with \"%s\": %s", xdmf_path,
                      temporary, reason);
    free(temporary);
    free(target);
    return status;
}
